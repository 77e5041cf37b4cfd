// Yaskawa INFORM job (.jbi): measurement programs and their joint positions read back.
//
// Grammar constraints relied on (what the controller's job loader checks):
// - `/JOB`, `//NAME name` (at most 8 characters on the older controllers, upper case),
//   `//POS`, `///NPOS c,bc,ec,p,bp,ex` whose first count equals the number of C variables
//   defined below, `///TOOL n`, `///POSTYPE PULSE`, `///PULSE`, then `Cnnnnn=p1,...,p6`
//   numbered from C00000 without gaps, then `//INST`, `///DATE yyyy/mm/dd hh:mm`,
//   `///ATTR SC,RW`, `///GROUP1 RB1`, `NOP`, the instructions, `END`;
// - joints are integer encoder pulses (pulses per degree from the robot's parameters), so a
//   configuration comes back to within half a pulse, exactly the rounded pulse count;
// - comments are lines starting with `'`, at most 32 characters;
// - MOVJ C..... VJ=speed% with PL=0 stops exactly (fine point); TIMER T=seconds waits.

#include <fmt/format.h>

#include <cmath>
#include <map>

#include "measurement_writers.hpp"
#include "robcal/core/error.hpp"

namespace robcal::detail {

std::string write_jbi_measurement(const MeasurementPart& part) {
  const MeasurementProgramRequest& r = part.request;
  const std::array<double, kJointCount>& ppd = *r.pulses_per_degree;
  std::string pulses;
  std::string inst;
  int c = 0;
  const auto move = [&](const Vector6d& q) {
    pulses += fmt::format("C{:05d}=", c);
    for (int j = 0; j < kJointCount; ++j) {
      const double p = std::round(q[j] * ppd[static_cast<size_t>(j)]);
      if (std::abs(p) > 2e9)
        throw InputError(
            SourceLocation{"", 0, 0, "--pulses-per-degree"},
            fmt::format("joint {} at {} deg is {} pulses: beyond a 32-bit count", j + 1, q[j], p));
      pulses += fmt::format("{}{:.0f}", j == 0 ? "" : ",", p);
    }
    pulses += "\n";
    inst += fmt::format("MOVJ C{:05d} VJ={:.2f} PL=0\n", c++, r.joint_speed_percent);
  };
  for (const Visit& v : part.visits) {
    inst += fmt::format("'{}\n", v.name);
    move(v.approach_deg);
    move(v.target_deg);
    inst += fmt::format("TIMER T={:.2f}\n", r.settle_s);
    if (r.hook == MeasurementHook::WaitInput)
      inst += fmt::format("WAIT IN#({})=ON\n", r.signal);
    else
      inst += fmt::format("PULSE OT#({}) T=0.50\n", r.signal);
  }
  return fmt::format(
      "/JOB\n//NAME {}\n//POS\n///NPOS {},0,0,0,0,0\n///TOOL {}\n///POSTYPE PULSE\n///PULSE\n"
      "{}//INST\n///DATE {}\n///ATTR SC,RW\n///GROUP1 RB1\nNOP\n{}END\n",
      part.program, c, r.tool_number, pulses, r.date, inst);
}

std::vector<JointMove> read_jbi_joint_moves(const std::string& text, const std::string& file,
                                            const std::array<double, kJointCount>& ppd) {
  std::map<int, Vector6d> positions;
  std::vector<std::pair<int, int>> order;  // (C index, line)
  int declared = -1;                       // ///NPOS first count
  bool in_pulse = false, in_inst = false;
  size_t at = 0;
  int number = 0;
  while (at < text.size()) {
    ++number;
    const size_t start = at;
    size_t end = text.find('\n', at);
    if (end == std::string::npos) end = text.size();
    std::string_view line(text.data() + start, end - start);
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    at = end + 1;
    const auto fail = [&](size_t column, const std::string& what) {
      throw InputError(SourceLocation{file, number, static_cast<int>(column) + 1, ""}, what);
    };
    // `Cnnnnn` at `pos`: the index.
    const auto c_index = [&](size_t pos) {
      size_t offset = start + pos + 1;
      const double index = read_number(text, offset, file, number, start);
      if (index != std::floor(index) || index < 0 || index > 99999)
        fail(pos, "expected a C variable C00000..C99999");
      return std::pair{static_cast<int>(index), offset - start};
    };
    if (line.starts_with("///NPOS ")) {
      size_t offset = start + 8;
      declared = static_cast<int>(read_number(text, offset, file, number, start));
    } else if (line.starts_with("///PULSE")) {
      in_pulse = true;
    } else if (line.starts_with("//INST")) {
      in_pulse = false;
      in_inst = true;
    } else if (line.starts_with("///RCONF") || line.starts_with("///TOOL") ||
               line.starts_with("///POSTYPE") || line.starts_with("///USER")) {
      if (line.starts_with("///POSTYPE") && line.find("PULSE") == std::string_view::npos)
        fail(11, "only ///POSTYPE PULSE positions are read");
    } else if (in_pulse && line.starts_with("C")) {
      const auto [index, after] = c_index(0);
      if (after >= line.size() || line[after] != '=') fail(after, "expected '='");
      Vector6d q;
      size_t offset = start + after + 1;
      for (int j = 0; j < kJointCount; ++j) {
        if (j > 0) {
          if (offset - start >= line.size() || line[offset - start] != ',')
            fail(offset - start, fmt::format("expected ',' and the pulses of axis {}", j + 1));
          ++offset;
        }
        q[j] = read_number(text, offset, file, number, start) / ppd[static_cast<size_t>(j)];
      }
      if (!positions.emplace(index, q).second) fail(0, fmt::format("C{:05d} defined twice", index));
    } else if (in_inst && line.starts_with("MOVJ C")) {
      order.emplace_back(c_index(5).first, number);
    }
  }
  if (declared != static_cast<int>(positions.size()))
    throw InputError(SourceLocation{file, 0, 0, "///NPOS"},
                     fmt::format("///NPOS declares {} C variables, the job defines {}", declared,
                                 positions.size()));
  std::vector<JointMove> moves;
  for (const auto& [index, line] : order) {
    const auto it = positions.find(index);
    if (it == positions.end())
      throw InputError(SourceLocation{file, line, 6, ""},
                       fmt::format("C{:05d} is not defined in //POS", index));
    moves.push_back({it->second, line});
  }
  return moves;
}

}  // namespace robcal::detail
