// Not yet implemented: issue #8 replaces this file with the real command.
#include "commands.hpp"
#include "s3m/core/error.hpp"

namespace s3m::apps {

void register_export(CLI::App& app) {
  auto* cmd = app.add_subcommand("export", "Export a semantic map (not implemented yet, issue #8)");
  cmd->allow_extras();
  cmd->callback([] { throw Error("'s3m export' is not implemented yet (issue #8)"); });
}

}  // namespace s3m::apps
