// The shading rule of multi-material SDF assets (hermite_sdf/core/materials.h), one for every
// method: the colour at a hit is the palette entry of the grid sample nearest to the hit -- for a
// cell its nearest corner, for the dense tracers the nearest sample of the grid, the same sample.
// The object's colour multiplies the entry's (white shows the materials as authored) and the
// roughness is the entry's. Included after hermite_host_device.h.
#ifndef HERMITE_MATERIALS_GLSL
#define HERMITE_MATERIALS_GLSL

// The corner (x + 2y + 4z) of a cell nearest to the cell-local point u: a coordinate of 0.5 or
// more goes to the upper corner (hsdf::nearestCorner).
uint nearestCorner(vec3 u) { return (u.x >= 0.5 ? 1u : 0u) + (u.y >= 0.5 ? 2u : 0u) + (u.z >= 0.5 ? 4u : 0u); }

// Byte i % 4 of a word of four slots.
uint slotInWord(uint word, uint i) { return (word >> (8u * (i & 3u))) & 0xffu; }

// The slot of corner `corner` of the record `record` of an asset's CellMaterialSlotsGpu[] at `slots`.
uint cellCornerSlot(uint64_t slots, uint record, uint corner) {
  CellMaterialSlotsGpu s = CellMaterialSlotsRef(slots).records[record];
  return slotInWord(corner < 4u ? s.corners0123 : s.corners4567, corner);
}

// Shades with palette entry `slot` of the HermiteMaterialGpu[] at `palette`: the object's colour
// times the entry's, the entry's roughness.
void applyPaletteEntry(uint64_t palette, uint slot, inout vec3 color, inout float roughness) {
  HermiteMaterialGpu m = PaletteRef(palette).entries[slot];
  color *= m.color.rgb;
  roughness = m.material.x;
}

// The dense tracers' materials block at `block` (FieldMaterialsHeader, the palette, the slots of
// the K^3 samples): the entry of the sample nearest to grid position g.
void applyFieldMaterial(uint64_t block, vec3 g, uint resolution, inout vec3 color, inout float roughness) {
  uvec3 s = uvec3(clamp(floor(g + 0.5), vec3(0.0), vec3(float(resolution - 1u))));
  uint index = s.x + resolution * (s.y + resolution * s.z);
  uint64_t words = block + uint64_t(FieldMaterialsRef(block).header.slotsOffset);
  uint slot = slotInWord(SlotWordsRef(words).words[index >> 2], index);
  HermiteMaterialGpu m = FieldMaterialsRef(block).palette[slot];
  color *= m.color.rgb;
  roughness = m.material.x;
}

#endif
