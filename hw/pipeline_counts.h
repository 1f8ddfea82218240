// The pipeline's counters that both models keep, defined by the golden model
// (docs/pipeline-spec.md, section 13): the golden model fills them as it
// renders, the cycle model from its stages' counters (Gpu::pipeline_counts),
// and `gpusim run --check` compares them field by field. Each field is
// listed once, in visit_fields; JSON, equality and the comparison follow.
#pragma once

#include <cstdint>
#include <nlohmann/json.hpp>
#include <ostream>
#include <string>
#include <vector>

namespace gpusim {

struct PipelineCounts {
  // Clears executed that wrote the colour (depth) buffer: the frame clear
  // and the draw list's (section 15).
  uint64_t color_clears = 0;
  uint64_t depth_clears = 0;
  uint64_t triangles_in = 0;            // assembled
  uint64_t triangles_invalid = 0;       // non-finite position or out-of-range index
  uint64_t triangles_clipped_away = 0;  // entirely outside the clip volume
  uint64_t triangles_clipped = 0;       // needed clipping and kept a part
  uint64_t triangles_after_clip = 0;    // triangles leaving the clipper
  uint64_t triangles_degenerate = 0;    // zero area after snapping
  uint64_t triangles_culled = 0;        // removed by face culling
  uint64_t triangles_rasterized = 0;    // set up and scanned
  uint64_t triangles_offscreen = 0;     // of those, no pixel centre in their box
  uint64_t triangles_unfilled = 0;      // drawn as lines or points (polygon mode)
  uint64_t lines_in = 0;                // assembled
  uint64_t lines_invalid = 0;           // non-finite position or out-of-range index
  uint64_t lines_clipped_away = 0;      // entirely outside the clip volume
  uint64_t lines_clipped = 0;           // needed clipping and kept a part
  uint64_t lines_degenerate = 0;        // diamond exit, zero length after snapping
  uint64_t lines_rasterized = 0;        // rasterized, polygon mode's included
  uint64_t points_in = 0;               // assembled
  uint64_t points_invalid = 0;          // non-finite position or out-of-range index
  uint64_t points_clipped_away = 0;     // outside the view volume
  uint64_t points_rasterized = 0;       // rasterized, polygon mode's included
  uint64_t fragments_generated = 0;     // covered pixels
  uint64_t fragments_passed_depth = 0;
  uint64_t fragments_written = 0;  // passed depth with a colour channel enabled
  // Antialiasing: the samples behind the fragment counts (equal to them
  // with one sample per pixel).
  uint64_t samples_generated = 0;
  uint64_t samples_passed_depth = 0;
  uint64_t samples_written = 0;

  // f(name, field) for every field, in the order above.
  template <typename F>
  void visit_fields(F&& f) {
    visit(*this, f);
  }
  template <typename F>
  void visit_fields(F&& f) const {
    visit(*this, f);
  }

  // {name: value} for every field (stats.json's `stats`), and back: every
  // field must be there as a non-negative integer (std::invalid_argument
  // "<name>: missing" otherwise); other keys are ignored.
  nlohmann::json to_json() const;
  static PipelineCounts from_json(const nlohmann::json& j);
  bool operator==(const PipelineCounts& o) const;
  bool operator!=(const PipelineCounts& o) const { return !(*this == o); }

 private:
  template <typename Self, typename F>
  static void visit(Self& s, F& f) {
    f("color_clears", s.color_clears);
    f("depth_clears", s.depth_clears);
    f("triangles_in", s.triangles_in);
    f("triangles_invalid", s.triangles_invalid);
    f("triangles_clipped_away", s.triangles_clipped_away);
    f("triangles_clipped", s.triangles_clipped);
    f("triangles_after_clip", s.triangles_after_clip);
    f("triangles_degenerate", s.triangles_degenerate);
    f("triangles_culled", s.triangles_culled);
    f("triangles_rasterized", s.triangles_rasterized);
    f("triangles_offscreen", s.triangles_offscreen);
    f("triangles_unfilled", s.triangles_unfilled);
    f("lines_in", s.lines_in);
    f("lines_invalid", s.lines_invalid);
    f("lines_clipped_away", s.lines_clipped_away);
    f("lines_clipped", s.lines_clipped);
    f("lines_degenerate", s.lines_degenerate);
    f("lines_rasterized", s.lines_rasterized);
    f("points_in", s.points_in);
    f("points_invalid", s.points_invalid);
    f("points_clipped_away", s.points_clipped_away);
    f("points_rasterized", s.points_rasterized);
    f("fragments_generated", s.fragments_generated);
    f("fragments_passed_depth", s.fragments_passed_depth);
    f("fragments_written", s.fragments_written);
    f("samples_generated", s.samples_generated);
    f("samples_passed_depth", s.samples_passed_depth);
    f("samples_written", s.samples_written);
  }
};

std::ostream& operator<<(std::ostream& os, const PipelineCounts& c);

// One field whose values differ between two sets of counts.
struct CountDifference {
  std::string name;
  uint64_t a = 0, b = 0;
};
// Every differing field, in field order.
std::vector<CountDifference> differences(const PipelineCounts& a, const PipelineCounts& b);

}  // namespace gpusim
