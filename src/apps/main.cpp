#include <iostream>

#include "commands.hpp"
#include "s3m/core/error.hpp"

int main(int argc, char** argv) {
  CLI::App app{"s3m: semantic RGB-D SLAM with a semantic OctoMap"};
  app.require_subcommand(1);
  app.set_version_flag("--version", "s3m 0.1.0");
  s3m::apps::register_eval(app);
  s3m::apps::register_sim(app);
  s3m::apps::register_run(app);
  s3m::apps::register_check(app);
  s3m::apps::register_merge(app);
  s3m::apps::register_batch(app);
  s3m::apps::register_demo(app);
  s3m::apps::register_segeval(app);
  s3m::apps::register_query(app);
  s3m::apps::register_plan(app);
  s3m::apps::register_export(app);
  s3m::apps::register_view(app);
  s3m::apps::register_vocab(app);
  s3m::apps::register_tum2bag(app);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  } catch (const s3m::apps::Interrupted& e) {
    std::cerr << "s3m: interrupted: " << e.what() << "\n";
    return 130;
  } catch (const s3m::Error& e) {
    std::cerr << "s3m: error: " << e.what() << "\n";
    return 1;
  } catch (const std::exception& e) {
    std::cerr << "s3m: unexpected error: " << e.what() << "\n";
    return 2;
  }
  return 0;
}
