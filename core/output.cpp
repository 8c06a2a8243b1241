#include "core/output.hpp"

#include <charconv>
#include <cstdio>
#include <fstream>
#include <regex>
#include <system_error>

#include <unistd.h>

#include "core/error.hpp"

namespace mps_lab {

namespace fs = std::filesystem;

void write_file_atomically(const fs::path& path, const std::string& content) {
  fs::path temporary = path;
  temporary += ".tmp." + std::to_string(::getpid());
  {
    std::FILE* file = std::fopen(temporary.c_str(), "wb");
    if (file == nullptr) {
      throw OutputError(path.string() + ": cannot write (" + std::error_code(errno, std::generic_category()).message() + ")");
    }
    const std::size_t written = std::fwrite(content.data(), 1, content.size(), file);
    const bool flushed = std::fflush(file) == 0;
    const int saved_errno = errno;
    const bool closed = std::fclose(file) == 0;
    if (written != content.size() || !flushed || !closed) {
      std::error_code ignored;
      fs::remove(temporary, ignored);
      throw OutputError(path.string() + ": write failed (" +
                        std::error_code(saved_errno, std::generic_category()).message() + ")");
    }
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
  static const std::regex previous(R"((output_\d{6,}\.(csv|vtk))|series\.csv|run\.json|output\.vtk\.series)");
  for (const auto& entry : fs::directory_iterator(directory_, error)) {
    const std::string name = entry.path().filename().string();
    if (entry.is_regular_file() && std::regex_match(name, previous)) {
      fs::remove(entry.path(), error);
      if (error) throw OutputError(entry.path().string() + ": cannot remove a previous run's file (" + error.message() + ")");
    }
  }
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
    write_file_atomically(directory_ / "output.vtk.series", index.dump(2) + "\n");
  }
  last_frame_step_ = step;
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
  write_file_atomically(directory_ / "run.json", summary.dump(2) + "\n");
}

}  // namespace mps_lab
