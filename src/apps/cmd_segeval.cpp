// Not yet implemented: issue #7 replaces this file with the real command.
#include "commands.hpp"
#include "s3m/core/error.hpp"

namespace s3m::apps {

void register_segeval(CLI::App& app) {
  auto* cmd = app.add_subcommand("segeval", "Evaluate segmentation against labels (not implemented yet, issue #7)");
  cmd->allow_extras();
  cmd->callback([] { throw Error("'s3m segeval' is not implemented yet (issue #7)"); });
}

}  // namespace s3m::apps
