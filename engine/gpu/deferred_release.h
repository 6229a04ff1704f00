#pragma once
// The one way to destroy a GPU object that commands of submitted frames may still use: retire it,
// and it is kept until those frames have completed and destroyed then, without waiting for the
// device (Granite's model, with frame numbers instead of one list per frame slot).
//
// The frame number rule. The renderer owns one DeferredRelease and hands it to every feature with
// the frame (render::FrameContext::retire). Frame F is recorded into frame slot F % framesInFlight
// after the renderer waited for that slot's fence, i.e. for frame F - framesInFlight; so while
// frame F is prepared every frame up to F - framesInFlight has completed, and an object last used
// by frame L can go once L + framesInFlight <= F (completed()). `lastUse` is the last frame whose
// commands may use the object: the frame being prepared for what it (or an earlier view region of
// it) has recorded with, or an earlier frame for what no later frame used (e.g. the previous use of
// a frame slot's own buffers, frameNumber - framesInFlight). The renderer collects at the start of
// every frame (after the fence wait) and again when the frame is recorded (what was retired with an
// already-completed lastUse goes in the frame that retired it), and destroys everything once the
// device is idle (collectAll()). A frame that fails while it is recorded is not submitted and its
// number is used again by the next frame, so what it retired is kept at least as long.
//
// Who decides that an object is unneeded (a feature's own policy, e.g. "not drawn for N frames")
// is not this class's business; it only decides when the object can be destroyed.
#include <cstddef>
#include <cstdint>
#include <memory>
#include <type_traits>
#include <utility>
#include <vector>

namespace engine::gpu {

class DeferredRelease {
 public:
  // Whether frame `lastUse` has surely completed when frame `frameNumber` is being prepared.
  static bool completed(std::uint64_t lastUse, std::uint64_t frameNumber, std::uint32_t framesInFlight) {
    return lastUse + framesInFlight <= frameNumber;
  }

  // Keeps `object` (any movable owner: a Buffer, an Image, a unique_ptr to a group of them) alive
  // until frame `lastUse`, the last frame whose commands may use it, has completed.
  template <class T>
  void retire(T&& object, std::uint64_t lastUse) {
    pending_.push_back({lastUse, std::make_shared<std::decay_t<T>>(std::forward<T>(object))});
  }

  // Destroys what only completed frames used, when frame `frameNumber` is being prepared.
  void collect(std::uint64_t frameNumber, std::uint32_t framesInFlight);
  // Destroys everything: only once the device is idle (no frame in flight).
  void collectAll() { pending_.clear(); }
  // Objects retired and not yet destroyed.
  std::size_t pending() const { return pending_.size(); }

 private:
  struct Entry {
    std::uint64_t lastUse = 0;
    std::shared_ptr<void> object;  // type-erased owner: its deleter runs the object's destructor
  };
  std::vector<Entry> pending_;
};

// A buffer sized by earlier frames that is given back once it has gone unneeded for a number of
// frames in a row (not at the first such frame: a view that swings back must not reallocate it).
// due() counts one more frame, and says when the count has reached `frames` (at least 1), starting
// again from there; a needed frame starts it again too.
class IdleFrames {
 public:
  bool due(bool unneeded, std::uint32_t frames) {
    count_ = unneeded ? count_ + 1 : 0;
    if (count_ < (frames > 0 ? frames : 1)) return false;
    count_ = 0;
    return true;
  }
  void reset() { count_ = 0; }

 private:
  std::uint32_t count_ = 0;
};

}  // namespace engine::gpu
