#include "core/io/output.hpp"

#include <algorithm>
#include <array>
#include <cerrno>
#include <charconv>
#include <condition_variable>
#include <cstdio>
#include <limits>
#include <mutex>
#include <regex>
#include <stdexcept>
#include <system_error>
#include <thread>

#include <fcntl.h>
#include <unistd.h>

#include "core/base/error.hpp"
#include "core/io/checkpoint.hpp"

namespace mps_lab {

namespace fs = std::filesystem;

namespace {

[[noreturn]] void throw_write_error(const fs::path& reported, const std::string& what, int error_number) {
  throw OutputError(reported.string() + ": " + what + " (" +
                    std::error_code(error_number, std::generic_category()).message() + ")");
}

}  // namespace

void write_file_checked(const fs::path& path, const FilePieces& content, const fs::path& reported_as) {
  const fs::path& reported = reported_as.empty() ? path : reported_as;
  const int descriptor = ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0666);
  if (descriptor < 0) throw_write_error(reported, "cannot write", errno);
  for (const std::string_view piece : content) {
    // write() may write less than asked (a signal, a pipe); loop until all is out or it fails.
    std::size_t done = 0;
    while (done < piece.size()) {
      const ssize_t written = ::write(descriptor, piece.data() + done, piece.size() - done);
      if (written < 0 && errno == EINTR) continue;
      if (written <= 0) {
        const int error_number = written < 0 ? errno : ENOSPC;  // 0 bytes for a non-empty write: no room
        ::close(descriptor);
        throw_write_error(reported, "write failed", error_number);
      }
      done += static_cast<std::size_t>(written);
    }
  }
  // Network file systems report a failed write only when the file is closed.
  if (::close(descriptor) != 0) throw_write_error(reported, "write failed on close", errno);
}

void write_file_checked(const fs::path& path, const std::string& content, const fs::path& reported_as) {
  write_file_checked(path, FilePieces{content}, reported_as);
}

void write_file_atomically(const fs::path& path, const FilePieces& content) {
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

void write_file_atomically(const fs::path& path, const std::string& content) {
  write_file_atomically(path, FilePieces{content});
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

void copy_frame(const ParticleSet& particles, const std::vector<FieldSpec>& fields, double time, long long step,
                const std::string& title, FrameData& frame) {
  frame.step = step;
  frame.time = time;
  frame.title = title;
  // In id order (ParticleSet::id): a row is the same particle in every frame, whatever order the
  // particles have in memory (cell-ordered particles, core/search/cell_order.hpp).
  const std::vector<std::uint32_t> by_id = indices_in_id_order(particles);
  const std::size_t n = particles.size() - particles.count(ParticleType::Ghost);
  // resize keeps the capacity: after the first frame, no allocation unless the set grew.
  frame.points.resize(3 * n);
  frame.velocity.resize(3 * n);
  frame.pressure.resize(n);
  frame.type.resize(n);
  std::size_t k = 0;
  for (const std::uint32_t i : by_id) {
    if (particles.type[i] == ParticleType::Ghost) continue;
    frame.points[3 * k] = particles.position[i].x();
    frame.points[3 * k + 1] = particles.position[i].y();
    frame.points[3 * k + 2] = 0.0;
    frame.velocity[3 * k] = particles.velocity[i].x();
    frame.velocity[3 * k + 1] = particles.velocity[i].y();
    frame.velocity[3 * k + 2] = 0.0;
    frame.pressure[k] = particles.pressure[i];
    frame.type[k] = static_cast<std::int32_t>(particles.type[i]);
    ++k;
  }
  frame.field_names.clear();
  for (const auto& field : fields) {
    if (field.written) frame.field_names.push_back(field.name);
  }
  frame.field_values.resize(frame.field_names.size());
  for (std::size_t f = 0; f < frame.field_names.size(); ++f) {
    const auto& values = particles.field(frame.field_names[f]);
    auto& copied = frame.field_values[f];
    copied.resize(n);
    k = 0;
    for (const std::uint32_t i : by_id) {
      if (particles.type[i] != ParticleType::Ghost) copied[k++] = values[i];
    }
  }
}

std::string csv_frame(const FrameData& frame) {
  const std::size_t n = frame.size();
  std::string out = "x,y,vx,vy,pressure,type\n";
  out.reserve(n * 80);
  for (std::size_t k = 0; k < n; ++k) {
    append(out, frame.points[3 * k]);
    out += ',';
    append(out, frame.points[3 * k + 1]);
    out += ',';
    append(out, frame.velocity[3 * k]);
    out += ',';
    append(out, frame.velocity[3 * k + 1]);
    out += ',';
    append(out, frame.pressure[k]);
    out += ',';
    out += std::to_string(frame.type[k]);
    out += '\n';
  }
  return out;
}

std::string vtk_frame(const FrameData& frame) {
  const std::size_t n = frame.size();
  std::string out;
  out.reserve(n * 160);
  out += "# vtk DataFile Version 3.0\n";
  out += frame.title + " step " + std::to_string(frame.step) + " time " + format_double(frame.time) + "\n";
  out += "ASCII\nDATASET UNSTRUCTURED_GRID\n";
  out += "FIELD FieldData 1\nTIME 1 1 double\n";
  append(out, frame.time);
  out += "\nPOINTS " + std::to_string(n) + " double\n";
  for (std::size_t k = 0; k < n; ++k) {
    append(out, frame.points[3 * k]);
    out += ' ';
    append(out, frame.points[3 * k + 1]);
    out += " 0\n";
  }
  out += "CELLS " + std::to_string(n) + " " + std::to_string(2 * n) + "\n";
  for (std::size_t k = 0; k < n; ++k) out += "1 " + std::to_string(k) + "\n";
  out += "CELL_TYPES " + std::to_string(n) + "\n";
  for (std::size_t k = 0; k < n; ++k) out += "1\n";  // VTK_VERTEX
  out += "POINT_DATA " + std::to_string(n) + "\n";
  out += "SCALARS pressure double 1\nLOOKUP_TABLE default\n";
  for (std::size_t k = 0; k < n; ++k) {
    append(out, frame.pressure[k]);
    out += '\n';
  }
  out += "SCALARS type int 1\nLOOKUP_TABLE default\n";
  for (std::size_t k = 0; k < n; ++k) out += std::to_string(frame.type[k]) + "\n";
  out += "VECTORS velocity double\n";
  for (std::size_t k = 0; k < n; ++k) {
    append(out, frame.velocity[3 * k]);
    out += ' ';
    append(out, frame.velocity[3 * k + 1]);
    out += " 0\n";
  }
  for (std::size_t f = 0; f < frame.field_names.size(); ++f) {
    out += "SCALARS " + frame.field_names[f] + " double 1\nLOOKUP_TABLE default\n";
    for (const double value : frame.field_values[f]) {
      append(out, value);
      out += '\n';
    }
  }
  return out;
}

// The appended block is the arrays' bytes as they are in memory: little endian only.
#if defined(__BYTE_ORDER__) && defined(__ORDER_LITTLE_ENDIAN__)
static_assert(__BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__, "the VTU writer assumes a little-endian machine");
#endif

namespace {

template <typename T>
std::string_view bytes_of(const std::vector<T>& values, std::size_t count) {
  return {reinterpret_cast<const char*>(values.data()), count * sizeof(T)};
}

}  // namespace

FilePieces vtu_frame(const FrameData& frame, VtuScratch& scratch) {
  const std::size_t n = frame.size();
  if (n >= static_cast<std::size_t>(std::numeric_limits<std::int32_t>::max())) {
    throw std::length_error(std::to_string(n) + " particles: more than the Int32 cell ids of the VTU frame allow");
  }
  // The cell arrays are the same for every frame: extend them once, use their first n.
  for (std::size_t k = scratch.connectivity.size(); k < n; ++k) {
    scratch.connectivity.push_back(static_cast<std::int32_t>(k));
    scratch.offsets.push_back(static_cast<std::int32_t>(k + 1));
    scratch.cell_types.push_back(1);  // VTK_VERTEX
  }

  // Each data array is one block of the appended data; its offset counts from the byte
  // after '_', and the block is its size (UInt64) followed by its bytes.
  std::vector<std::string_view> blocks;
  std::string& xml = scratch.header;
  xml.clear();
  std::uint64_t offset = 0;
  const auto data_array = [&](const char* type, const std::string& name, int components, std::string_view bytes) {
    xml += "<DataArray type=\"";
    xml += type;
    xml += "\" Name=\"" + name + "\"";
    if (components > 1) xml += " NumberOfComponents=\"" + std::to_string(components) + "\"";
    xml += " format=\"appended\" offset=\"" + std::to_string(offset) + "\"/>\n";
    blocks.push_back(bytes);
    offset += sizeof(std::uint64_t) + bytes.size();
  };
  const std::string count = std::to_string(n);
  xml += "<?xml version=\"1.0\"?>\n";
  xml += "<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\">\n";
  xml += "<UnstructuredGrid>\n<FieldData>\n";
  xml += "<DataArray type=\"Float64\" Name=\"TIME\" NumberOfTuples=\"1\" format=\"appended\" offset=\"0\"/>\n";
  blocks.emplace_back(reinterpret_cast<const char*>(&frame.time), sizeof frame.time);
  offset += sizeof(std::uint64_t) + sizeof frame.time;
  xml += "</FieldData>\n";
  xml += "<Piece NumberOfPoints=\"" + count + "\" NumberOfCells=\"" + count + "\">\n";
  xml += "<PointData Scalars=\"pressure\" Vectors=\"velocity\">\n";
  data_array("Float64", "pressure", 1, bytes_of(frame.pressure, n));
  data_array("Int32", "type", 1, bytes_of(frame.type, n));
  data_array("Float64", "velocity", 3, bytes_of(frame.velocity, 3 * n));
  for (std::size_t f = 0; f < frame.field_names.size(); ++f) {
    data_array("Float64", frame.field_names[f], 1, bytes_of(frame.field_values[f], n));
  }
  xml += "</PointData>\n<Points>\n";
  data_array("Float64", "Points", 3, bytes_of(frame.points, 3 * n));
  xml += "</Points>\n<Cells>\n";
  data_array("Int32", "connectivity", 1, bytes_of(scratch.connectivity, n));
  data_array("Int32", "offsets", 1, bytes_of(scratch.offsets, n));
  data_array("UInt8", "types", 1, bytes_of(scratch.cell_types, n));
  xml += "</Cells>\n</Piece>\n</UnstructuredGrid>\n";
  xml += "<AppendedData encoding=\"raw\">\n_";
  scratch.footer = "\n</AppendedData>\n</VTKFile>\n";

  scratch.block_bytes.resize(blocks.size());  // before any view into it is taken
  FilePieces pieces = {xml};
  for (std::size_t b = 0; b < blocks.size(); ++b) {
    scratch.block_bytes[b] = blocks[b].size();
    pieces.emplace_back(reinterpret_cast<const char*>(&scratch.block_bytes[b]), sizeof(std::uint64_t));
    pieces.push_back(blocks[b]);
  }
  pieces.emplace_back(scratch.footer);
  return pieces;
}

std::string pvd_index(const std::vector<std::pair<double, std::string>>& frames) {
  std::string out = "<?xml version=\"1.0\"?>\n";
  out += "<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n<Collection>\n";
  for (const auto& [time, name] : frames) {
    out += "<DataSet timestep=\"" + format_double(time) + "\" group=\"\" part=\"0\" file=\"" + name + "\"/>\n";
  }
  out += "</Collection>\n</VTKFile>\n";
  return out;
}

// The frame writer. The simulation thread fills jobs[filling] while the writing thread
// writes jobs[1 - filling] (when in_flight); hand_over swaps them. `filling` and `in_flight`
// change under `mutex` only, and the simulation thread swaps only when nothing is in flight.
struct RunOutput::FrameWriter {
  struct Job {
    FrameData frame;
    std::vector<FrameRecord> index;  // every frame so far, this one last
  };

  FrameWriter(fs::path folder, FrameFormats frame_formats, FrameWriting writing)
      : directory(std::move(folder)), formats(frame_formats) {
    if (writing == FrameWriting::background) thread = std::thread([this] { run(); });
  }
  ~FrameWriter() {
    if (!thread.joinable()) return;
    {
      const std::lock_guard<std::mutex> lock(mutex);
      stopping = true;
    }
    changed.notify_all();
    thread.join();  // the frame in flight, if any, is finished first
  }
  FrameWriter(const FrameWriter&) = delete;
  FrameWriter& operator=(const FrameWriter&) = delete;

  Job& job_to_fill() { return jobs[filling]; }

  void wait_until_idle() {
    std::unique_lock<std::mutex> lock(mutex);
    changed.wait(lock, [this] { return !in_flight; });
  }

  // The first failure of a frame ("" if none); it stays, so that every later call reports it.
  std::string failure() {
    const std::lock_guard<std::mutex> lock(mutex);
    return failure_message;
  }

  // Hands jobs[filling] over (call after wait_until_idle); without a thread, writes it now
  // and throws its failure.
  void hand_over() {
    if (!thread.joinable()) {
      std::string failed = write_job(jobs[filling]);
      if (failed.empty()) return;
      if (failure_message.empty()) failure_message = failed;
      throw OutputError(failed);
    }
    {
      const std::lock_guard<std::mutex> lock(mutex);
      filling = 1 - filling;
      in_flight = true;
    }
    changed.notify_all();
  }

  // The writing thread: one job at a time until stopped with nothing in flight.
  void run() {
    std::unique_lock<std::mutex> lock(mutex);
    for (;;) {
      changed.wait(lock, [this] { return in_flight || stopping; });
      if (!in_flight) return;
      const Job& job = jobs[1 - filling];
      lock.unlock();
      std::string failed = write_job(job);
      lock.lock();
      if (failure_message.empty()) failure_message = std::move(failed);
      in_flight = false;
      changed.notify_all();
    }
  }

  // Writes the frame's files and the indexes; returns the failure ("" on success). The
  // frame file first, then the index that lists it: an index never names a missing file.
  std::string write_job(const Job& job) {
    fs::path current = directory;
    try {
      const std::string stem = frame_stem(job.frame.step);
      if (formats.csv) {
        current = directory / (stem + ".csv");
        write_file_atomically(current, csv_frame(job.frame));
      }
      if (formats.vtk) {
        current = directory / (stem + ".vtk");
        write_file_atomically(current, vtk_frame(job.frame));
        // ParaView's JSON file-series index: open output.vtk.series to get every frame with its time.
        nlohmann::json index = {{"file-series-version", "1.0"}, {"files", nlohmann::json::array()}};
        for (const auto& record : job.index) {
          index["files"].push_back({{"name", frame_stem(record.step) + ".vtk"}, {"time", record.time}});
        }
        current = directory / "output.vtk.series";
        write_file_atomically(current, index.dump(2, ' ', false, nlohmann::json::error_handler_t::replace) + "\n");
      }
      if (formats.vtu) {
        current = directory / (stem + ".vtu");
        write_file_atomically(current, vtu_frame(job.frame, vtu_scratch));
        std::vector<std::pair<double, std::string>> listed;
        listed.reserve(job.index.size());
        for (const auto& record : job.index) listed.emplace_back(record.time, frame_stem(record.step) + ".vtu");
        current = directory / "output.pvd";
        write_file_atomically(current, pvd_index(listed));
      }
    } catch (const OutputError& error) {
      return error.what();  // names the file already
    } catch (const std::exception& error) {
      return current.string() + ": " + error.what();
    } catch (...) {
      return current.string() + ": unknown error while writing";
    }
    return {};
  }

  const fs::path directory;
  const FrameFormats formats;
  std::array<Job, 2> jobs;
  int filling = 0;
  VtuScratch vtu_scratch;  // used by the writing thread only
  std::mutex mutex;
  std::condition_variable changed;
  bool in_flight = false;
  bool stopping = false;
  std::string failure_message;
  std::thread thread;  // last: started when everything it uses exists
};

RunOutput::RunOutput(fs::path directory, FrameFormats formats, std::vector<std::string> series_columns,
                     FrameWriting writing)
    : directory_(std::move(directory)),
      formats_(formats),
      series_columns_(std::move(series_columns)),
      writer_(std::make_unique<FrameWriter>(directory_, formats_, writing)) {
  for (const auto& column : series_columns_) series_text_ += (series_text_.empty() ? "" : ",") + column;
  series_text_ += '\n';
}

RunOutput::~RunOutput() = default;

namespace {

// The files a run writes, and the temporary files write_file_atomically leaves behind when
// a process is killed in the middle of a write.
const std::regex& run_file_pattern() {
  static const std::regex pattern(
      R"(((output_\d{6,}\.(csv|vtk|vtu))|series\.csv|run\.json|output\.vtk\.series|output\.pvd|checkpoint\.bin)(\.tmp\.\d+)?)");
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

void RunOutput::rethrow_write_failure() {
  std::string failure = writer_->failure();
  if (!failure.empty()) throw OutputError(failure);
}

void RunOutput::write_frame(const ParticleSet& particles, const std::vector<FieldSpec>& fields, double time,
                            long long step, const std::string& title) {
  rethrow_write_failure();
  // Copy while the previous frame may still be being written (it is in the other buffer).
  FrameWriter::Job& job = writer_->job_to_fill();
  copy_frame(particles, fields, time, step, title, job.frame);
  writer_->wait_until_idle();
  rethrow_write_failure();  // the previous frame failed: it is reported before this one is counted
  frames_.push_back({step, time});
  job.index = frames_;
  writer_->hand_over();
}

void RunOutput::flush() {
  writer_->wait_until_idle();
  rethrow_write_failure();
}

void RunOutput::prepare_resume() {
  if (!fs::is_directory(directory_) || ::access(directory_.c_str(), W_OK | X_OK) != 0) {
    throw OutputError(directory_.string() + ": the run folder is not a writable folder");
  }
  static const std::regex frame(R"(output_(\d{6,})\.(csv|vtk|vtu))");
  static const std::regex temporary(R"(.*\.tmp\.\d+)");
  std::error_code error;
  for (const auto& entry : fs::directory_iterator(directory_, error)) {
    const std::string name = entry.path().filename().string();
    if (!entry.is_regular_file() || !std::regex_match(name, run_file_pattern())) continue;
    std::smatch match;
    const bool stray_temporary = std::regex_match(name, temporary);
    const bool unlisted_frame =
        std::regex_match(name, match, frame) &&
        std::none_of(frames_.begin(), frames_.end(),
                     [step = std::stoll(match[1].str())](const FrameRecord& record) { return record.step == step; });
    if (stray_temporary || unlisted_frame) remove_file(entry.path());
  }
  if (error) throw OutputError(directory_.string() + ": cannot list the run folder (" + error.message() + ")");
}

void RunOutput::save_state(CheckpointWriter& out) {
  flush();  // the checkpoint lists frames that are on disk
  out.write_string(series_text_);
  out.write_size(frames_.size());
  for (const auto& record : frames_) {
    out.write_int(record.step);
    out.write_double(record.time);
  }
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
  series_unwritten_ = true;
  frames_.resize(in.read_size());
  for (auto& record : frames_) {
    record.step = in.read_int();
    record.time = in.read_double();
  }
}

void RunOutput::add_series_row(const std::vector<double>& values) {
  rethrow_write_failure();
  if (values.size() != series_columns_.size()) {
    throw std::logic_error("series row has " + std::to_string(values.size()) + " values for " +
                           std::to_string(series_columns_.size()) + " columns");
  }
  for (std::size_t k = 0; k < values.size(); ++k) {
    if (k > 0) series_text_ += ',';
    append(series_text_, values[k]);
  }
  series_text_ += '\n';
  series_unwritten_ = true;
}

void RunOutput::write_series() {
  rethrow_write_failure();
  if (!series_unwritten_) return;
  write_file_atomically(directory_ / "series.csv", series_text_);
  series_unwritten_ = false;
  series_written_at_ = std::chrono::steady_clock::now();
}

void RunOutput::write_series_when_due() {
  rethrow_write_failure();
  if (series_written_at_ != std::chrono::steady_clock::time_point{} &&
      std::chrono::steady_clock::now() - series_written_at_ < series_rewrite_period_) {
    return;
  }
  write_series();
}

void RunOutput::write_summary(const nlohmann::json& summary) {
  flush();         // run.json describes frames that are on disk
  write_series();  // and the rows so far
  // A scene path or --set value in another encoding must not stop the summary being written.
  write_file_atomically(directory_ / "run.json",
                        summary.dump(2, ' ', false, nlohmann::json::error_handler_t::replace) + "\n");
}

}  // namespace mps_lab
