// Not yet implemented: issue #9 replaces this file with the real command.
#include "commands.hpp"
#include "s3m/core/error.hpp"

namespace s3m::apps {

void register_demo(CLI::App& app) {
  auto* cmd = app.add_subcommand("demo", "Simulate, run and report in one go (not implemented yet, issue #9)");
  cmd->allow_extras();
  cmd->callback([] { throw Error("'s3m demo' is not implemented yet (issue #9)"); });
}

}  // namespace s3m::apps
