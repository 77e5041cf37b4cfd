#pragma once
// A refusal test asserts what the refusal says, not only that something was thrown: a message
// that names the wrong place or says nothing useful is a bug too.

#include <gtest/gtest.h>

#include <string>

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
