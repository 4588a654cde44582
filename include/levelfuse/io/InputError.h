// levelfuse: the error every reader throws for bad input.
#pragma once

#include <stdexcept>
#include <string>

namespace levelfuse::io {

/// Bad input: names the file and says what is wrong with it, e.g.
/// "scans/bun000.ply: line 27: vertex 3 has 2 values, the header declares 3".
class InputError : public std::runtime_error {
 public:
  InputError(const std::string& file, const std::string& problem)
      : std::runtime_error(file + ": " + problem), mFile(file), mProblem(problem) {}
  const std::string& file() const { return mFile; }
  const std::string& problem() const { return mProblem; }

 private:
  std::string mFile, mProblem;
};

}  // namespace levelfuse::io
