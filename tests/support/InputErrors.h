// Assertions on the errors readers throw for bad input.
#pragma once

#include <levelfuse/io/InputError.h>

#include <gtest/gtest.h>

#include <string>

namespace levelfuse::test {

/// Expects f() to throw an InputError that names `file` (in its message too)
/// and says `fragment`.
template <typename F>
void expectInputError(F&& f, const std::string& file, const std::string& fragment) {
  try {
    f();
    ADD_FAILURE() << "no error (expected '" << fragment << "')";
  } catch (const io::InputError& e) {
    EXPECT_EQ(e.file(), file);
    EXPECT_NE(std::string(e.what()).find(file), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
  }
}

}  // namespace levelfuse::test
