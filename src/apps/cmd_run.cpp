// Not yet implemented: issue #9 replaces this file with the real command.
#include "commands.hpp"
#include "s3m/core/error.hpp"

namespace s3m::apps {

void register_run(CLI::App& app) {
  auto* cmd = app.add_subcommand("run", "Run the pipeline on a TUM-layout dataset (not implemented yet, issue #9)");
  cmd->allow_extras();
  cmd->callback([] { throw Error("'s3m run' is not implemented yet (issue #9)"); });
}

}  // namespace s3m::apps
