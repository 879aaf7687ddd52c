#include "bench/protocols/registry.h"

#include "bench/protocols/classification.h"
#include "bench/protocols/detection.h"
#include "bench/protocols/multi_view.h"
#include "bench/protocols/single_frame.h"
#include "bench/protocols/stereo_pair.h"

namespace grapebench {

namespace {

// Protocols read their keys in the scene's `pipeline:` section (pipeline_param_table
// says which key each protocol reads), so their registry lines carry none.
struct NoKeys {};

RegistryEntry<ProtocolRun> protocol(std::string type, std::string summary, CaseRun run, CasesRun together = {}) {
  return entry<ProtocolRun>(std::move(type), std::move(summary), ParamTable<NoKeys>(), NoKeys{},
                            [run = ProtocolRun{std::move(run), std::move(together)}](const NoKeys&, const ConfigNode&) {
                              return run;
                            });
}

}  // namespace

const Registry<ProtocolRun>& protocol_registry() {
  static const Registry<ProtocolRun> registry(
      "protocol",
      {
          protocol("multi_view",
                   "scan, segment, register, merge, filter, estimate: one registered cloud per bunch (seeds 000, 002)",
                   run_multi_view),
          protocol("single_frame", "per frame: pass-through, ROIs, fine tuning, estimate; no registration (seed 003)",
                   run_single_frame),
          protocol("stereo_pair",
                   "per station: one rectified colour stereo pair; cutting point, berries, cluster region, bounding "
                   "volume scored against the exact scene (seed 001)",
                   run_stereo_pair, run_stereo_pair_together),
          protocol("classification",
                   "a vine-row section, a camera pass made into one coloured cloud, a training and a separate test "
                   "part; class scores per test point rated against the exact labels (seed 004)",
                   run_classification),
          protocol("detection",
                   "per view: one colour image; instances (boxes, masks) scored by COCO's AP against the exact visible "
                   "instances, berry count per bunch, volume per detected bunch (issue 42)",
                   run_detection),
      });
  return registry;
}

}  // namespace grapebench
