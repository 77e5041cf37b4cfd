#include "robcal/report/provenance.hpp"

#include <fmt/format.h>

#include <array>
#include <cstdint>
#include <ctime>
#include <fstream>

#include <yaml-cpp/yaml.h>

#include "robcal/io/atomic_file.hpp"

#ifndef ROBCAL_VERSION
#define ROBCAL_VERSION "unknown"
#endif

namespace robcal {
namespace {

constexpr std::array<uint32_t, 64> kRound = {
    0x428a2f98, 0x71374491, 0xb5c0fbcf, 0xe9b5dba5, 0x3956c25b, 0x59f111f1, 0x923f82a4, 0xab1c5ed5,
    0xd807aa98, 0x12835b01, 0x243185be, 0x550c7dc3, 0x72be5d74, 0x80deb1fe, 0x9bdc06a7, 0xc19bf174,
    0xe49b69c1, 0xefbe4786, 0x0fc19dc6, 0x240ca1cc, 0x2de92c6f, 0x4a7484aa, 0x5cb0a9dc, 0x76f988da,
    0x983e5152, 0xa831c66d, 0xb00327c8, 0xbf597fc7, 0xc6e00bf3, 0xd5a79147, 0x06ca6351, 0x14292967,
    0x27b70a85, 0x2e1b2138, 0x4d2c6dfc, 0x53380d13, 0x650a7354, 0x766a0abb, 0x81c2c92e, 0x92722c85,
    0xa2bfe8a1, 0xa81a664b, 0xc24b8b70, 0xc76c51a3, 0xd192e819, 0xd6990624, 0xf40e3585, 0x106aa070,
    0x19a4c116, 0x1e376c08, 0x2748774c, 0x34b0bcb5, 0x391c0cb3, 0x4ed8aa4a, 0x5b9cca4f, 0x682e6ff3,
    0x748f82ee, 0x78a5636f, 0x84c87814, 0x8cc70208, 0x90befffa, 0xa4506ceb, 0xbef9a3f7, 0xc67178f2};

constexpr uint32_t rotr(uint32_t x, int n) {
  return (x >> n) | (x << (32 - n));
}

/// One 64-byte block into the state (FIPS 180-4 §6.2.2).
void compress(std::array<uint32_t, 8>& h, const unsigned char* block) {
  std::array<uint32_t, 64> w{};
  for (int t = 0; t < 16; ++t)
    w[t] = uint32_t(block[4 * t]) << 24 | uint32_t(block[4 * t + 1]) << 16 |
           uint32_t(block[4 * t + 2]) << 8 | uint32_t(block[4 * t + 3]);
  for (int t = 16; t < 64; ++t) {
    const uint32_t s0 = rotr(w[t - 15], 7) ^ rotr(w[t - 15], 18) ^ (w[t - 15] >> 3);
    const uint32_t s1 = rotr(w[t - 2], 17) ^ rotr(w[t - 2], 19) ^ (w[t - 2] >> 10);
    w[t] = w[t - 16] + s0 + w[t - 7] + s1;
  }
  std::array<uint32_t, 8> v = h;
  for (int t = 0; t < 64; ++t) {
    const uint32_t S1 = rotr(v[4], 6) ^ rotr(v[4], 11) ^ rotr(v[4], 25);
    const uint32_t ch = (v[4] & v[5]) ^ (~v[4] & v[6]);
    const uint32_t t1 = v[7] + S1 + ch + kRound[t] + w[t];
    const uint32_t S0 = rotr(v[0], 2) ^ rotr(v[0], 13) ^ rotr(v[0], 22);
    const uint32_t maj = (v[0] & v[1]) ^ (v[0] & v[2]) ^ (v[1] & v[2]);
    v = {t1 + S0 + maj, v[0], v[1], v[2], v[3] + t1, v[4], v[5], v[6]};
  }
  for (int i = 0; i < 8; ++i) h[i] += v[i];
}

}  // namespace

std::string robcal_version() {
  return ROBCAL_VERSION;
}

std::string utc_now() {
  const std::time_t now = std::time(nullptr);
  std::tm utc{};
  gmtime_r(&now, &utc);
  return fmt::format("{:04}-{:02}-{:02}T{:02}:{:02}:{:02}Z", utc.tm_year + 1900, utc.tm_mon + 1,
                     utc.tm_mday, utc.tm_hour, utc.tm_min, utc.tm_sec);
}

std::string sha256_hex(std::string_view bytes) {
  std::array<uint32_t, 8> h = {0x6a09e667, 0xbb67ae85, 0x3c6ef372, 0xa54ff53a,
                               0x510e527f, 0x9b05688c, 0x1f83d9ab, 0x5be0cd19};
  const size_t whole = bytes.size() / 64 * 64;
  for (size_t i = 0; i < whole; i += 64)
    compress(h, reinterpret_cast<const unsigned char*>(bytes.data()) + i);
  // Padding (§5.1.1): 0x80, zeros, the length in bits as 64-bit big endian.
  std::array<unsigned char, 128> tail{};
  const size_t rest = bytes.size() - whole;
  std::copy(bytes.begin() + static_cast<std::ptrdiff_t>(whole), bytes.end(), tail.begin());
  tail[rest] = 0x80;
  const size_t blocks = rest + 9 <= 64 ? 1 : 2;
  const uint64_t bits = static_cast<uint64_t>(bytes.size()) * 8;
  for (int k = 0; k < 8; ++k)
    tail[blocks * 64 - 1 - k] = static_cast<unsigned char>(bits >> (8 * k));
  for (size_t b = 0; b < blocks; ++b) compress(h, tail.data() + 64 * b);
  std::string out;
  for (const uint32_t word : h) out += fmt::format("{:08x}", word);
  return out;
}

ProvenanceFile provenance_file(const std::string& role, const std::string& path) {
  return {role, path, sha256_hex(read_text_file(path))};
}

Provenance start_provenance(int argc, const char* const* argv) {
  Provenance p;
  p.robcal_version = robcal_version();
  p.date_utc = utc_now();
  for (int i = 0; i < argc; ++i) {
    const std::string_view arg = argv[i];
    if (i > 0) p.command_line += ' ';
    p.command_line += arg.find_first_of(" \t'\"") == std::string_view::npos
                          ? std::string(arg)
                          : fmt::format("'{}'", arg);
  }
  return p;
}

Provenance start_provenance_of_process() {
  std::vector<std::string> args;
  std::ifstream in("/proc/self/cmdline", std::ios::binary);
  for (std::string arg; std::getline(in, arg, '\0');) args.push_back(arg);
  std::vector<const char*> argv;
  argv.reserve(args.size());
  for (const std::string& a : args) argv.push_back(a.c_str());
  return start_provenance(static_cast<int>(argv.size()), argv.data());
}

nlohmann::json provenance_json(const Provenance& p) {
  nlohmann::json out = {{"robcal_version", p.robcal_version},
                        {"date_utc", p.date_utc},
                        {"command_line", p.command_line},
                        {"robot", p.robot},
                        {"level", p.level},
                        {"instrument", p.instrument}};
  out["instrument_sigma_mm"] =
      p.instrument_sigma_mm ? nlohmann::json(*p.instrument_sigma_mm) : nlohmann::json(nullptr);
  out["seed"] = p.seed ? nlohmann::json(*p.seed) : nlohmann::json(nullptr);
  out["files"] = nlohmann::json::array();
  for (const ProvenanceFile& f : p.files)
    out["files"].push_back({{"role", f.role}, {"path", f.path}, {"sha256", f.sha256}});
  return out;
}

void emit_provenance(YAML::Emitter& out, const Provenance& p) {
  out << YAML::BeginMap;
  out << YAML::Key << "robcal_version" << YAML::Value << p.robcal_version;
  out << YAML::Key << "date_utc" << YAML::Value << p.date_utc;
  out << YAML::Key << "command_line" << YAML::Value << p.command_line;
  out << YAML::Key << "robot" << YAML::Value << p.robot;
  out << YAML::Key << "level" << YAML::Value << p.level;
  if (!p.instrument.empty()) out << YAML::Key << "instrument" << YAML::Value << p.instrument;
  if (p.instrument_sigma_mm)
    out << YAML::Key << "instrument_sigma_mm" << YAML::Value << *p.instrument_sigma_mm;
  if (p.seed) out << YAML::Key << "seed" << YAML::Value << *p.seed;
  out << YAML::Key << "files" << YAML::Value << YAML::BeginSeq;
  for (const ProvenanceFile& f : p.files)
    out << YAML::BeginMap << YAML::Key << "role" << YAML::Value << f.role << YAML::Key << "path"
        << YAML::Value << f.path << YAML::Key << "sha256" << YAML::Value << f.sha256
        << YAML::EndMap;
  out << YAML::EndSeq << YAML::EndMap;
}

}  // namespace robcal
