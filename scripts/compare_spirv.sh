#!/usr/bin/env bash
# compare_spirv.sh OLD_DIR NEW_DIR: compares two folders of SPIR-V (build/<preset>/shaders of two
# builds), each file byte for byte and again with its debug instructions stripped and its ids
# compacted (spirv-opt --strip-debug --compact-ids), the check that a build change left the code
# the same while -g's file names, source text and line numbers moved. Lists what differs; exits 1
# when a file's code differs or a name is in one folder only.
set -euo pipefail
if [[ $# -ne 2 || ! -d $1 || ! -d $2 ]]; then
  echo "usage: $0 OLD_SHADER_DIR NEW_SHADER_DIR (two folders of .spv files)" >&2
  exit 2
fi
old=$1
new=$2
scratch=$(mktemp -d)
trap 'rm -rf "$scratch"' EXIT
status=0
names_only=$(diff <(cd "$old" && ls -- *.spv) <(cd "$new" && ls -- *.spv) || true)
if [[ -n $names_only ]]; then
  echo "names in one folder only:"
  echo "$names_only"
  status=1
fi
total=0 same_bytes=0 same_code=0
for path in "$new"/*.spv; do
  name=$(basename "$path")
  [[ -f $old/$name ]] || continue
  total=$((total + 1))
  if cmp -s "$old/$name" "$path"; then same_bytes=$((same_bytes + 1)); fi
  spirv-opt --strip-debug --compact-ids "$old/$name" -o "$scratch/old.spv"
  spirv-opt --strip-debug --compact-ids "$path" -o "$scratch/new.spv"
  if cmp -s "$scratch/old.spv" "$scratch/new.spv"; then
    same_code=$((same_code + 1))
  else
    echo "code differs: $name"
    status=1
  fi
done
echo "$total files in both: $same_bytes identical byte for byte, $same_code identical without debug instructions"
exit $status
