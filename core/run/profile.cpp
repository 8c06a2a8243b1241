#include "core/run/profile.hpp"

#include <algorithm>
#include <cstdio>
#include <fstream>

#include <sys/resource.h>
#include <unistd.h>

namespace mps_lab {

PhaseTimers::Id PhaseTimers::phase(const std::string& name) {
  for (Id id = 0; id < phases_.size(); ++id) {
    if (phases_[id].name == name) return id;
  }
  phases_.push_back({name, 0.0, 0});
  return phases_.size() - 1;
}

double PhaseTimers::seconds(const std::string& name) const {
  for (const auto& phase : phases_) {
    if (phase.name == name) return phase.seconds;
  }
  return 0.0;
}

long long PhaseTimers::calls(const std::string& name) const {
  for (const auto& phase : phases_) {
    if (phase.name == name) return phase.calls;
  }
  return 0;
}

double PhaseTimers::total_seconds() const {
  double total = 0.0;
  for (const auto& phase : phases_) total += phase.seconds;
  return total;
}

void PhaseTimers::reset() {
  for (auto& phase : phases_) {
    phase.seconds = 0.0;
    phase.calls = 0;
  }
}

nlohmann::json profile_json(const PhaseTimers& timers, double wall_seconds, long long steps,
                            std::size_t fluid_particles) {
  const auto entry = [&](double seconds, long long calls) {
    return nlohmann::json{{"seconds", seconds},
                          {"calls", calls},
                          {"share", wall_seconds > 0.0 ? seconds / wall_seconds : 0.0},
                          {"milliseconds_per_step", steps > 0 ? 1e3 * seconds / static_cast<double>(steps) : 0.0}};
  };
  nlohmann::json phases = nlohmann::json::object();
  for (const auto& phase : timers.phases()) {
    if (phase.calls > 0) phases[phase.name] = entry(phase.seconds, phase.calls);
  }
  phases["other"] = entry(std::max(0.0, wall_seconds - timers.total_seconds()), 0);
  return {{"wall_seconds", wall_seconds},
          {"steps", steps},
          {"fluid_particles", fluid_particles},
          {"fluid_particle_steps_per_second",
           wall_seconds > 0.0 ? static_cast<double>(fluid_particles) * static_cast<double>(steps) / wall_seconds : 0.0},
          {"phases", phases}};
}

std::string profile_table(const nlohmann::json& profile) {
  std::vector<std::pair<std::string, nlohmann::json>> rows;
  for (const auto& item : profile.at("phases").items()) rows.emplace_back(item.key(), item.value());
  std::stable_sort(rows.begin(), rows.end(), [](const auto& a, const auto& b) {
    return a.second.at("seconds").template get<double>() > b.second.at("seconds").template get<double>();
  });
  std::string out;
  char line[160];
  std::snprintf(line, sizeof line, "profile: %lld steps, %zu fluid particles, %.3f s, %.3g fluid particle-steps/s\n",
                profile.at("steps").get<long long>(), profile.at("fluid_particles").get<std::size_t>(),
                profile.at("wall_seconds").get<double>(), profile.at("fluid_particle_steps_per_second").get<double>());
  out += line;
  std::snprintf(line, sizeof line, "  %-18s %10s %7s %12s %9s\n", "phase", "seconds", "share", "ms/step", "calls");
  out += line;
  for (const auto& [name, phase] : rows) {
    std::snprintf(line, sizeof line, "  %-18s %10.3f %6.1f%% %12.4f %9lld\n", name.c_str(),
                  phase.at("seconds").get<double>(), 100.0 * phase.at("share").get<double>(),
                  phase.at("milliseconds_per_step").get<double>(), phase.at("calls").get<long long>());
    out += line;
  }
  return out;
}

std::size_t resident_memory_bytes() {
  std::ifstream statm("/proc/self/statm");
  std::size_t pages_total = 0, pages_resident = 0;
  statm >> pages_total >> pages_resident;
  return pages_resident * static_cast<std::size_t>(::sysconf(_SC_PAGESIZE));
}

double process_cpu_seconds() {
  rusage usage{};
  ::getrusage(RUSAGE_SELF, &usage);
  const auto seconds = [](const timeval& t) {
    return static_cast<double>(t.tv_sec) + 1e-6 * static_cast<double>(t.tv_usec);
  };
  return seconds(usage.ru_utime) + seconds(usage.ru_stime);
}

std::size_t peak_resident_memory_bytes() {
  rusage usage{};
  ::getrusage(RUSAGE_SELF, &usage);
  return static_cast<std::size_t>(usage.ru_maxrss) * 1024;  // ru_maxrss is in KiB on Linux
}

}  // namespace mps_lab
