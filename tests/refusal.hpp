#pragma once
// A refusal test asserts what the refusal says, not only that something was thrown: a message
// that names the wrong place or says nothing useful is a bug too.

#include <gtest/gtest.h>

#include <string>

#include "robcal/core/error.hpp"

namespace robcal::test {

/// The message of the InputError `f` throws, "" when it throws none.
template <typename F>
std::string refusal_message(F&& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

}  // namespace robcal::test

/// Expects `statement` to throw `Exception` with `fragment` in its message.
#define EXPECT_REFUSED(statement, Exception, fragment)                          \
  do {                                                                          \
    try {                                                                       \
      statement;                                                                \
      ADD_FAILURE() << "no " #Exception " from " #statement;                    \
    } catch (const Exception& refusal_) {                                       \
      EXPECT_NE(std::string(refusal_.what()).find(fragment), std::string::npos) \
          << "message of " #statement ": " << refusal_.what();                  \
    }                                                                           \
  } while (0)
