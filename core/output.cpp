#include "core/output.hpp"

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cstdio>
#include <fstream>
#include <regex>
#include <system_error>

#include <fcntl.h>
#include <unistd.h>

#include "core/checkpoint.hpp"
#include "core/error.hpp"

namespace mps_lab {

namespace fs = std::filesystem;

namespace {

[[noreturn]] void throw_write_error(const fs::path& reported, const std::string& what, int error_number) {
  throw OutputError(reported.string() + ": " + what + " (" +
                    std::error_code(error_number, std::generic_category()).message() + ")");
}

}  // namespace

void write_file_checked(const fs::path& path, const std::string& content, const fs::path& reported_as) {
  const fs::path& reported = reported_as.empty() ? path : reported_as;
  const int descriptor = ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0666);
  if (descriptor < 0) throw_write_error(reported, "cannot write", errno);
  // write() may write less than asked (a signal, a pipe); loop until all is out or it fails.
  std::size_t done = 0;
  while (done < content.size()) {
    const ssize_t written = ::write(descriptor, content.data() + done, content.size() - done);
    if (written < 0 && errno == EINTR) continue;
    if (written <= 0) {
      const int error_number = written < 0 ? errno : ENOSPC;  // 0 bytes for a non-empty write: no room
      ::close(descriptor);
      throw_write_error(reported, "write failed", error_number);
    }
    done += static_cast<std::size_t>(written);
  }
  // Network file systems report a failed write only when the file is closed.
  if (::close(descriptor) != 0) throw_write_error(reported, "write failed on close", errno);
}

void write_file_atomically(const fs::path& path, const std::string& content) {
  fs::path temporary = path;
  temporary += ".tmp." + std::to_string(::getpid());
  try {
    write_file_checked(temporary, content, path);
  } catch (const OutputError&) {
    std::error_code ignored;
    fs::remove(temporary, ignored);  // never leave a partial file behind
    throw;
  }
  std::error_code error;
  fs::rename(temporary, path, error);
  if (error) {
    std::error_code ignored;
    fs::remove(temporary, ignored);
    throw OutputError(path.string() + ": cannot rename the finished file into place (" + error.message() + ")");
  }
}

std::string format_double(double value) {
  char buffer[32];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, value);
  return std::string(buffer, result.ptr);
}

std::string frame_stem(long long step) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "output_%06lld", step);
  return buffer;
}

namespace {

void append(std::string& out, double value) {
  char buffer[32];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, value);
  out.append(buffer, result.ptr);
}

}  // namespace

std::string csv_frame(const ParticleSet& particles) {
  std::string out = "x,y,vx,vy,pressure,type\n";
  out.reserve(particles.size() * 80);
  for (std::size_t i = 0; i < particles.size(); ++i) {
    if (particles.type[i] == ParticleType::Ghost) continue;
    append(out, particles.position[i].x());
    out += ',';
    append(out, particles.position[i].y());
    out += ',';
    append(out, particles.velocity[i].x());
    out += ',';
    append(out, particles.velocity[i].y());
    out += ',';
    append(out, particles.pressure[i]);
    out += ',';
    out += std::to_string(static_cast<int>(particles.type[i]));
    out += '\n';
  }
  return out;
}

std::string vtk_frame(const ParticleSet& particles, const std::vector<FieldSpec>& fields, double time,
                      long long step, const std::string& title) {
  std::vector<std::size_t> written;
  for (std::size_t i = 0; i < particles.size(); ++i) {
    if (particles.type[i] != ParticleType::Ghost) written.push_back(i);
  }
  const std::size_t n = written.size();
  std::string out;
  out.reserve(n * 160);
  out += "# vtk DataFile Version 3.0\n";
  out += title + " step " + std::to_string(step) + " time " + format_double(time) + "\n";
  out += "ASCII\nDATASET UNSTRUCTURED_GRID\n";
  out += "FIELD FieldData 1\nTIME 1 1 double\n";
  append(out, time);
  out += "\nPOINTS " + std::to_string(n) + " double\n";
  for (std::size_t i : written) {
    append(out, particles.position[i].x());
    out += ' ';
    append(out, particles.position[i].y());
    out += " 0\n";
  }
  out += "CELLS " + std::to_string(n) + " " + std::to_string(2 * n) + "\n";
  for (std::size_t k = 0; k < n; ++k) out += "1 " + std::to_string(k) + "\n";
  out += "CELL_TYPES " + std::to_string(n) + "\n";
  for (std::size_t k = 0; k < n; ++k) out += "1\n";  // VTK_VERTEX
  out += "POINT_DATA " + std::to_string(n) + "\n";
  out += "SCALARS pressure double 1\nLOOKUP_TABLE default\n";
  for (std::size_t i : written) {
    append(out, particles.pressure[i]);
    out += '\n';
  }
  out += "SCALARS type int 1\nLOOKUP_TABLE default\n";
  for (std::size_t i : written) out += std::to_string(static_cast<int>(particles.type[i])) + "\n";
  out += "VECTORS velocity double\n";
  for (std::size_t i : written) {
    append(out, particles.velocity[i].x());
    out += ' ';
    append(out, particles.velocity[i].y());
    out += " 0\n";
  }
  for (const auto& field : fields) {
    if (!field.written) continue;
    const auto& values = particles.field(field.name);
    out += "SCALARS " + field.name + " double 1\nLOOKUP_TABLE default\n";
    for (std::size_t i : written) {
      append(out, values[i]);
      out += '\n';
    }
  }
  return out;
}

RunOutput::RunOutput(fs::path directory, bool csv, bool vtk, std::vector<std::string> series_columns)
    : directory_(std::move(directory)), csv_(csv), vtk_(vtk), series_columns_(std::move(series_columns)) {
  for (const auto& column : series_columns_) series_text_ += (series_text_.empty() ? "" : ",") + column;
  series_text_ += '\n';
}

namespace {

// The files a run writes, and the temporary files write_file_atomically leaves behind when
// a process is killed in the middle of a write.
const std::regex& run_file_pattern() {
  static const std::regex pattern(
      R"(((output_\d{6,}\.(csv|vtk))|series\.csv|run\.json|output\.vtk\.series|checkpoint\.bin)(\.tmp\.\d+)?)");
  return pattern;
}

void remove_file(const fs::path& path) {
  std::error_code error;
  fs::remove(path, error);
  if (error) throw OutputError(path.string() + ": cannot remove a previous run's file (" + error.message() + ")");
}

}  // namespace

void RunOutput::prepare() {
  std::error_code error;
  fs::create_directories(directory_, error);
  if (error || !fs::is_directory(directory_)) {
    throw OutputError(directory_.string() + ": cannot create the output folder (" +
                      (error ? error.message() : std::string("a file of that name exists")) + ")");
  }
  if (::access(directory_.c_str(), W_OK | X_OK) != 0) {
    throw OutputError(directory_.string() + ": the output folder is not writable");
  }
  // A previous run's files would mix with this run's frames: remove exactly those.
  for (const auto& entry : fs::directory_iterator(directory_, error)) {
    const std::string name = entry.path().filename().string();
    if (entry.is_regular_file() && std::regex_match(name, run_file_pattern())) remove_file(entry.path());
  }
  if (error) throw OutputError(directory_.string() + ": cannot list the output folder (" + error.message() + ")");
  // Probe: a folder can pass access() and still refuse files (read-only mount, full disk).
  write_file_atomically(directory_ / "series.csv", series_text_);
}

void RunOutput::write_frame(const ParticleSet& particles, const std::vector<FieldSpec>& fields, double time,
                            long long step, const std::string& title) {
  const std::string stem = frame_stem(step);
  if (csv_) write_file_atomically(directory_ / (stem + ".csv"), csv_frame(particles));
  if (vtk_) {
    write_file_atomically(directory_ / (stem + ".vtk"), vtk_frame(particles, fields, time, step, title));
    frames_.emplace_back(time, stem + ".vtk");
    // ParaView's JSON file-series index: open output.vtk.series to get every frame with its time.
    nlohmann::json index = {{"file-series-version", "1.0"}, {"files", nlohmann::json::array()}};
    for (const auto& [frame_time, name] : frames_) index["files"].push_back({{"name", name}, {"time", frame_time}});
    write_file_atomically(directory_ / "output.vtk.series",
                          index.dump(2, ' ', false, nlohmann::json::error_handler_t::replace) + "\n");
  }
  frame_steps_.push_back(step);
  last_frame_step_ = step;
}

void RunOutput::prepare_resume() {
  if (!fs::is_directory(directory_) || ::access(directory_.c_str(), W_OK | X_OK) != 0) {
    throw OutputError(directory_.string() + ": the run folder is not a writable folder");
  }
  static const std::regex frame(R"(output_(\d{6,})\.(csv|vtk))");
  static const std::regex temporary(R"(.*\.tmp\.\d+)");
  std::error_code error;
  for (const auto& entry : fs::directory_iterator(directory_, error)) {
    const std::string name = entry.path().filename().string();
    if (!entry.is_regular_file() || !std::regex_match(name, run_file_pattern())) continue;
    std::smatch match;
    const bool stray_temporary = std::regex_match(name, temporary);
    const bool unlisted_frame =
        std::regex_match(name, match, frame) &&
        std::find(frame_steps_.begin(), frame_steps_.end(), std::stoll(match[1].str())) == frame_steps_.end();
    if (stray_temporary || unlisted_frame) remove_file(entry.path());
  }
  if (error) throw OutputError(directory_.string() + ": cannot list the run folder (" + error.message() + ")");
}

void RunOutput::save_state(CheckpointWriter& out) const {
  out.write_string(series_text_);
  out.write_size(frames_.size());
  for (const auto& [time, name] : frames_) {
    out.write_double(time);
    out.write_string(name);
  }
  out.write_size(frame_steps_.size());
  for (long long step : frame_steps_) out.write_int(step);
  out.write_int(last_frame_step_);
}

void RunOutput::restore_state(CheckpointReader& in) {
  std::string header;
  for (const auto& column : series_columns_) header += (header.empty() ? "" : ",") + column;
  header += '\n';
  std::string series = in.read_string();
  if (series.compare(0, header.size(), header) != 0) {
    in.fail("series.csv columns differ from this build's: " + series.substr(0, series.find('\n')));
  }
  series_text_ = std::move(series);
  frames_.resize(in.read_size());
  for (auto& [time, name] : frames_) {
    time = in.read_double();
    name = in.read_string();
  }
  frame_steps_.resize(in.read_size());
  for (long long& step : frame_steps_) step = in.read_int();
  last_frame_step_ = in.read_int();
}

void RunOutput::add_series_row(const std::vector<double>& values) {
  if (values.size() != series_columns_.size()) {
    throw std::logic_error("series row has " + std::to_string(values.size()) + " values for " +
                           std::to_string(series_columns_.size()) + " columns");
  }
  for (std::size_t k = 0; k < values.size(); ++k) {
    if (k > 0) series_text_ += ',';
    append(series_text_, values[k]);
  }
  series_text_ += '\n';
}

void RunOutput::write_series() { write_file_atomically(directory_ / "series.csv", series_text_); }

void RunOutput::write_summary(const nlohmann::json& summary) {
  // A scene path or --set value in another encoding must not stop the summary being written.
  write_file_atomically(directory_ / "run.json",
                        summary.dump(2, ' ', false, nlohmann::json::error_handler_t::replace) + "\n");
}

}  // namespace mps_lab
