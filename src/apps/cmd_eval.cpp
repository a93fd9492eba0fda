// Not yet implemented: issue #3 replaces this file with the real command.
#include "commands.hpp"
#include "s3m/core/error.hpp"

namespace s3m::apps {

void register_eval(CLI::App& app) {
  auto* cmd = app.add_subcommand("eval", "Evaluate trajectories (ATE/RPE) against ground truth (not implemented yet, issue #3)");
  cmd->allow_extras();
  cmd->callback([] { throw Error("'s3m eval' is not implemented yet (issue #3)"); });
}

}  // namespace s3m::apps
