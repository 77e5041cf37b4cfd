#pragma once
// The operator's side of a guided session (campaign::SessionIo) from a Python list of answers:
// the point session and the hexapod session read them the same way.
#include <string>
#include <vector>

#include "robcal/campaign/session_workflow.hpp"

namespace robcal::python {

/// Answers fed one per prompt until the list ends (the session pauses); what the session says
/// is kept as its transcript, the answers it refuses (asked again) with their reasons.
struct ListedAnswers {
  std::vector<std::string> lines;
  size_t next = 0;
  std::string transcript;
  std::vector<std::string> refused;

  [[nodiscard]] campaign::SessionIo io() {
    return {[this](const std::string& text) { transcript += text; },
            [this](const std::string& why) { refused.push_back(why); },
            [this](std::string& line) {
              if (next >= lines.size()) return false;
              line = lines[next++];
              return true;
            },
            {}};
  }
};

}  // namespace robcal::python
