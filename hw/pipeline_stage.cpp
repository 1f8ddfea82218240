#include "hw/pipeline_stage.h"

namespace gpusim {

void PipelineStage::reset() {
  m_stats.reset();
  reset_state();
  m_local = kernel_stamp();
  // Each of the stage's threads unwinds from the wait it sleeps in and runs
  // again from its first statement, at once, until its first wait.
  for (sc_core::sc_object* child : get_child_objects()) {
    sc_core::sc_process_handle process(child);
    if (process.valid()) process.reset();
  }
}

}  // namespace gpusim
