// Not yet implemented: issue #4 replaces this file with the real command.
#include "commands.hpp"
#include "s3m/core/error.hpp"

namespace s3m::apps {

void register_sim(CLI::App& app) {
  auto* cmd = app.add_subcommand("sim", "Render a synthetic RGB-D sequence (not implemented yet, issue #4)");
  cmd->allow_extras();
  cmd->callback([] { throw Error("'s3m sim' is not implemented yet (issue #4)"); });
}

}  // namespace s3m::apps
