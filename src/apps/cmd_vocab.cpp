// Not yet implemented: issue #6 replaces this file with the real command.
#include "commands.hpp"
#include "s3m/core/error.hpp"

namespace s3m::apps {

void register_vocab(CLI::App& app) {
  auto* cmd = app.add_subcommand("vocab", "Train a bag-of-words vocabulary (not implemented yet, issue #6)");
  cmd->allow_extras();
  cmd->callback([] { throw Error("'s3m vocab' is not implemented yet (issue #6)"); });
}

}  // namespace s3m::apps
