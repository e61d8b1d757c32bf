// sinkwatch: the ground command line. Each subcommand lives with its tool;
// this file only assembles them.
#include <CLI/CLI.hpp>

#include <cstdio>

int main(int argc, char** argv) {
  CLI::App app{"sinkwatch: wheel-sinkage estimation and embedding prevention for planetary rovers"};
  app.require_subcommand(1);
  app.set_version_flag("--version", "sinkwatch 0.1.0");
  CLI11_PARSE(app, argc, argv);
  return 0;
}
