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

class CheckpointWriter;
class CheckpointReader;

// Writes `content` to `path` (created or emptied) and closes it, checking every call: a
// full disk shows up as a failed write() or close(), never as an exception by itself. A
// failure is an OutputError "<reported_as or path>: <what failed> (<errno text>)".
void write_file_checked(const std::filesystem::path& path, const std::string& content,
                        const std::filesystem::path& reported_as = {});

// write_file_checked to "<path>.tmp.<pid>", then rename onto `path`: readers see the old
// file or the complete new one. On failure the temporary file is removed.
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
  // (frames, series.csv, run.json, the index, checkpoint.bin, temporary files of those),
  // and nothing else.
  void prepare();
  // For a resumed run, after restore_state: checks that the folder is writable and removes
  // the frames that the restored bookkeeping does not list (written after the checkpoint
  // by a run that was killed, or the extra frame of an interruption) and temporary files.
  void prepare_resume();
  void write_frame(const ParticleSet& particles, const std::vector<FieldSpec>& fields, double time,
                   long long step, const std::string& title);
  void add_series_row(const std::vector<double>& values);  // one value per column
  void write_series();  // rewrites series.csv atomically with every row so far
  void write_summary(const nlohmann::json& summary);  // run.json

  // Checkpoints: the series rows so far and the frames written (core/checkpoint.hpp).
  void save_state(CheckpointWriter& out) const;
  void restore_state(CheckpointReader& in);

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
  std::vector<long long> frame_steps_;                   // every frame written, csv or vtk
  long long last_frame_step_ = -1;
};

}  // namespace mps_lab
