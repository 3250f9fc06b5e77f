#pragma once
// The loaders' bad-input contract, checked one way: a UserError of one line
// that names the file and says what is wrong.
#include <gtest/gtest.h>

#include <string>

#include "host/util/Error.hpp"

namespace ml::test {

// Runs `load`, which must throw a one-line UserError naming `path` and
// containing `also` (any message contains "").
template <class Load>
void expectFileError(Load&& load, const std::string& path, const std::string& also = "") {
  try {
    load();
    ADD_FAILURE() << "no error for " << path;
  } catch (const UserError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find(path), std::string::npos) << msg;
    EXPECT_NE(msg.find(also), std::string::npos) << msg;
    EXPECT_EQ(msg.find('\n'), std::string::npos) << msg;
  }
}

}  // namespace ml::test
