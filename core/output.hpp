#pragma once
// Run output: the spec's frames (CSV and VTK legacy ASCII, spec §10), the ParaView time
// index, series.csv and run.json. Every file is written atomically (to a temporary name
// in the same folder, then renamed), so a run killed at any moment leaves only complete
// files; a failed write is an OutputError naming the file.
#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/method.hpp"
#include "core/particles.hpp"

namespace mps_lab {

void write_file_atomically(const std::filesystem::path& path, const std::string& content);

// Shortest decimal text that reads back to the same double.
std::string format_double(double value);

// "output_000100" for step 100 (6-digit zero-padded step, spec §10; wider past 999999).
std::string frame_stem(long long step);

// Spec §10.1: header "x,y,vx,vy,pressure,type", one line per non-ghost particle.
std::string csv_frame(const ParticleSet& particles);

// Spec §10.2: VTK legacy ASCII 3.0, UNSTRUCTURED_GRID of VTK_VERTEX cells with point data
// pressure (double), type (int), velocity (double vector), then the method's written
// fields; the simulated time is stored as field data TIME. Ghosts are not written.
std::string vtk_frame(const ParticleSet& particles, const std::vector<FieldSpec>& fields, double time,
                      long long step, const std::string& title);

class RunOutput {
 public:
  RunOutput(std::filesystem::path directory, bool csv, bool vtk, std::vector<std::string> series_columns);

  // Creates the folder, checks it is writable, removes a previous run's files from it
  // (frames, series.csv, run.json, the index), and nothing else.
  void prepare();
  void write_frame(const ParticleSet& particles, const std::vector<FieldSpec>& fields, double time,
                   long long step, const std::string& title);
  void add_series_row(const std::vector<double>& values);  // one value per column
  void write_series();  // rewrites series.csv atomically with every row so far
  void write_summary(const nlohmann::json& summary);  // run.json

  const std::filesystem::path& directory() const { return directory_; }
  long long last_frame_step() const { return last_frame_step_; }
  std::size_t frames_written() const { return frames_.size(); }

 private:
  std::filesystem::path directory_;
  bool csv_;
  bool vtk_;
  std::vector<std::string> series_columns_;
  std::string series_text_;
  std::vector<std::pair<double, std::string>> frames_;  // (time, vtk file) for the index
  long long last_frame_step_ = -1;
};

}  // namespace mps_lab
