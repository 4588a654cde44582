#include "Support.h"

#include "Cancellation.h"

#include <levelfuse/io/InputError.h>
#include <levelfuse/io/InputFile.h>
#include <levelfuse/recon/SurfaceWeight.h>

#include <cmath>
#include <cstdlib>
#include <sstream>
#include <stdexcept>

namespace levelfuse::cli {

ThreadLimit::ThreadLimit(int threads) {
  if (threads > 0)
    mControl = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism,
                                                     static_cast<std::size_t>(threads));
}

CLI::Validator numberIn(double lo, double hi, bool aboveLo) {
  const std::string range = (aboveLo ? "(" : "[") + fixed(lo, 6) + ", " + fixed(hi, 6) + "]";
  return CLI::Validator(
      [=](std::string& text) -> std::string {
        char* end = nullptr;
        const double x = std::strtod(text.c_str(), &end);
        const bool inRange = aboveLo ? x > lo && x <= hi : x >= lo && x <= hi;
        if (text.empty() || end != text.c_str() + text.size() || !std::isfinite(x) || !inRange)
          return io::quote(text) + " is not a number in " + range;
        return "";
      },
      "in " + range);
}

CLI::Validator threeNumbers() {
  return CLI::Validator(
      [](std::string& text) -> std::string {
        try {
          parseVec3(text);
        } catch (const std::invalid_argument& e) {
          return e.what();
        }
        return "";
      },
      "x,y,z");
}

void requireOutputs(const std::vector<std::string>& outputs, const std::vector<std::string>& inputs) {
  std::vector<std::string> given;
  for (const std::string& path : outputs)
    if (!path.empty()) {
      io::requireWritable(path);
      given.push_back(path);
    }
  io::refuseOverwritingInputs(given, inputs);
}

void commitOutputs(io::OutputSet& outputs) {
  io::refuseOverwritingInputs(outputs.targets(), io::inputsRead());
  checkCancellation();
  outputs.commit();
}

std::string joined(const std::vector<std::string>& items) {
  std::string s;
  for (const std::string& item : items) s += (s.empty() ? "" : ", ") + item;
  return s;
}

std::string withCommas(std::size_t n) {
  std::string digits = std::to_string(n), out;
  for (std::size_t i = 0; i < digits.size(); ++i) {
    if (i > 0 && (digits.size() - i) % 3 == 0) out += ',';
    out += digits[i];
  }
  return out;
}

std::string fixed(double value, int digits) {
  std::ostringstream s;
  s.precision(digits);
  s << value;
  return s.str();
}

std::string mebibytes(std::size_t bytes) { return fixed(static_cast<double>(bytes) / 1048576.0, 3) + " MiB"; }

openvdb::math::Vec3d parseVec3(const std::string& text) {
  std::vector<double> v;
  std::stringstream s(text);
  std::string item;
  while (std::getline(s, item, ',')) {
    std::size_t used = 0;
    double x = 0.0;
    try {
      x = std::stod(item, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used == 0 || used != item.size() || !std::isfinite(x))
      throw std::invalid_argument(io::quote(text) + " is not three numbers x,y,z");
    v.push_back(x);
  }
  if (v.size() != 3) throw std::invalid_argument(io::quote(text) + " is not three numbers x,y,z");
  return openvdb::math::Vec3d(v[0], v[1], v[2]);
}

void addTrimUnseenOptions(CLI::App* cmd, std::optional<bool>& trim, const std::string& outputs,
                          const std::string& byDefault) {
  CLI::Option* on = cmd->add_flag_callback(
      "--trim-unseen", [&trim] { trim = true; },
      outputs + ": leave out the surface no scan observed (fewer than " + fixed(kObservedWeight) +
          " readings face it; the .vdb stays closed). " + byDefault);
  CLI::Option* off =
      cmd->add_flag_callback("--no-trim-unseen", [&trim] { trim = false; }, outputs + ": the whole closed surface");
  on->excludes(off);
}

}  // namespace levelfuse::cli
