// `gpusim trace follow DIR --prim N | --pixel X,Y`: one primitive's way
// through the pipeline (transactions.bin), or every fragment that touched one
// pixel (fragments.bin), streamed from the trace so a large frame's records
// are never all in memory. When nothing is found, the text says why: the
// primitive or pixel was filtered out (naming the filter from manifest.json)
// or was dropped before the stages that record it; a primitive id the scene
// does not have is an error.
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "traces/trace_reader.h"

namespace gpusim {

class TraceFollow {
 public:
  struct Step {
    const TraceStage* stage = nullptr;  // into the reader's manifest
    TransactionRecord record;
  };

  // `reader` must outlive this object.
  explicit TraceFollow(const TraceReader& reader) : m_reader(reader) {}

  // Work items carrying `prim`, in pipeline order, then by cycle_in, then unit.
  std::vector<Step> prim_steps(int64_t prim) const;
  // Fragments at pixel (x, y) (GL window coordinates), in time order; at
  // equal cycles the depth test before the ROP.
  std::vector<FragmentRecord> pixel_fragments(int x, int y) const;

  // The frame's final colour and depth at a pixel, for the last line of the
  // pixel report; nullopt when unknown. A callback so this library needs no
  // image I/O: the command line reads DIR/frame.exr.
  struct PixelValue {
    float rgba[4];
    float depth;
  };
  using FrameLookup = std::function<std::optional<PixelValue>(int x, int y)>;

  // The report `gpusim trace follow` prints. An (x, y) outside the
  // framebuffer, a negative primitive or one beyond the scene's primitives
  // is an InputError; a primitive filtered out or never recorded is
  // explained in the report.
  std::string prim_text(int64_t prim) const;
  std::string pixel_text(int x, int y, const FrameLookup& frame = nullptr) const;

 private:
  // Why `prim` has no records, from the manifest's filters and draws.
  std::string prim_absence(int64_t prim) const;
  const TraceReader& m_reader;
};

}  // namespace gpusim
