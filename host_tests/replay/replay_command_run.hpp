// One `sinkwatch replay` command line run in-process, its exit code and its
// two output streams: shared by the replay command's tests.
#pragma once

#include <sstream>
#include <string>
#include <vector>

#include "sinkwatch/ground/replay_command.hpp"

namespace sinkwatch::ground::test {

struct CommandRun {
  int code;
  std::string out;
  std::string err;
};

inline CommandRun run(const std::vector<std::string>& args) {
  std::ostringstream out;
  std::ostringstream err;
  const int code = run_replay_command(args, out, err);
  return CommandRun{code, out.str(), err.str()};
}

}  // namespace sinkwatch::ground::test
