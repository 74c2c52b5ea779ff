#include "apps/refine_options.h"

#include <memory>
#include <string>

#include "apps/fields_cli.h"
#include "f2c/util/error.h"

namespace f2c::app {

std::function<void()> AddRefineOptions(CLI::App* cmd, RefineOptions* o) {
  AddFieldFlags(cmd, o);  // every field of RefineOptions (refine/refine.h)
  // A shorthand over several fields, so not a field of its own.
  auto schedule = std::make_shared<std::string>("constant");
  cmd->add_option("--weight-schedule", *schedule,
                  "constant: the *-initial options as given; authors: every term's first weight 1.5 times its last "
                  "(E_C, E_P, E_H, E_G), as their 1500 -> 1000")
      ->capture_default_str()
      ->group("Refinement: planar structure (paper 4.2-4.3)");
  return [o, schedule] {
    if (*schedule == "authors") {
      o->weight_correspondence_initial = 1.5 * o->solver.weight_correspondence;
      o->weight_proxy_initial = 1.5 * o->solver.weight_proxy;
      o->weight_coplanarity_initial = 1.5 * o->solver.weight_coplanarity;
      o->weight_relation_initial = 1.5 * o->solver.weight_relation;
    } else if (*schedule != "constant") {
      throw InputError("--weight-schedule: unknown value '" + *schedule + "' (constant, authors)");
    }
  };
}

}  // namespace f2c::app
