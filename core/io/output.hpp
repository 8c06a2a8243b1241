#pragma once
// Run output: the spec's frames (CSV and VTK legacy ASCII, spec §10), VTK XML binary frames
// (.vtu) for large runs, the ParaView time indexes, series.csv and run.json. Every file is
// written atomically (to a temporary name in the same folder, then renamed), so a run killed
// at any moment leaves only complete files; a failed write is an OutputError naming the file.
//
// Frames are written by a background thread: write_frame copies the particles and returns
// while the previous copy is still being formatted and written (at most one frame in
// flight). A failed background write is an OutputError at the next call of RunOutput.
#include <chrono>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/base/particles.hpp"
#include "core/run/method.hpp"

namespace mps_lab {

class CheckpointWriter;
class CheckpointReader;

// The content of a file as consecutive pieces (views into storage that outlives the write),
// so that large binary arrays are written where they are, without being copied into one string.
using FilePieces = std::vector<std::string_view>;

// Writes `content` to `path` (created or emptied) and closes it, checking every call: a
// full disk shows up as a failed write() or close(), never as an exception by itself. A
// failure is an OutputError "<reported_as or path>: <what failed> (<errno text>)".
void write_file_checked(const std::filesystem::path& path, const std::string& content,
                        const std::filesystem::path& reported_as = {});
void write_file_checked(const std::filesystem::path& path, const FilePieces& content,
                        const std::filesystem::path& reported_as = {});

// write_file_checked to "<path>.tmp.<pid>", then rename onto `path`: readers see the old
// file or the complete new one. On failure the temporary file is removed.
void write_file_atomically(const std::filesystem::path& path, const std::string& content);
void write_file_atomically(const std::filesystem::path& path, const FilePieces& content);

// Shortest decimal text that reads back to the same double.
std::string format_double(double value);

// "output_000100" for step 100 (6-digit zero-padded step, spec §10; wider past 999999).
std::string frame_stem(long long step);

// One frame: the non-ghost particles copied out of a ParticleSet, in the layout of the VTU
// file's arrays (points and velocities as (x, y, 0) triples).
struct FrameData {
  long long step = 0;
  double time = 0.0;                              // s
  std::string title;                              // the VTK legacy header line starts with it
  std::vector<double> points;                     // m, 3 per particle: x, y, 0
  std::vector<double> velocity;                   // m/s, 3 per particle: vx, vy, 0
  std::vector<double> pressure;                   // Pa
  std::vector<std::int32_t> type;                 // ParticleType values (0 fluid, 1 wall)
  std::vector<std::string> field_names;           // the method's written fields, in order
  std::vector<std::vector<double>> field_values;  // one array per name

  std::size_t size() const { return pressure.size(); }
};

// Fills `frame` (reusing its storage) with the non-ghost particles and the written fields.
void copy_frame(const ParticleSet& particles, const std::vector<FieldSpec>& fields, double time, long long step,
                const std::string& title, FrameData& frame);

// Spec §10.1: header "x,y,vx,vy,pressure,type", one line per particle of the frame.
std::string csv_frame(const FrameData& frame);

// Spec §10.2: VTK legacy ASCII 3.0, UNSTRUCTURED_GRID of VTK_VERTEX cells with point data
// pressure (double), type (int), velocity (double vector), then the method's written
// fields; the simulated time is stored as field data TIME.
std::string vtk_frame(const FrameData& frame);

// The parts of a VTU file that do not depend on the particles' values: the cell arrays
// (the same for every frame of up to their length), the XML text and the block sizes.
// Reused from frame to frame by one writer.
struct VtuScratch {
  std::vector<std::int32_t> connectivity;  // 0, 1, 2, ...
  std::vector<std::int32_t> offsets;       // 1, 2, 3, ...
  std::vector<std::uint8_t> cell_types;    // 1 (VTK_VERTEX) each
  std::vector<std::uint64_t> block_bytes;  // the UInt64 size header of each appended block
  std::string header;                      // the XML up to and including the '_' of AppendedData
  std::string footer;
};

// VTK XML UnstructuredGrid, version 1.0, appended raw binary data (header_type UInt64,
// little endian): the same point data as vtk_frame, points as Float64 (x, y, 0), VTK_VERTEX
// cells with Int32 connectivity and offsets, TIME as field data. The pieces point into
// `frame` and `scratch`, which must outlive the write.
FilePieces vtu_frame(const FrameData& frame, VtuScratch& scratch);

// The ParaView collection (.pvd) of VTU frames: (time in s, file name) in order.
std::string pvd_index(const std::vector<std::pair<double, std::string>>& frames);

// Which frame files a run writes (the scene's output.formats).
struct FrameFormats {
  bool csv = true;
  bool vtk = true;
  bool vtu = false;
};

// How often a run rewrites series.csv at most (wall time): a rewrite of 3.3 MB (11,600 rows of 19
// columns) took 5.3 ms on average (measured, 2026-11-29), so a 1 s period bounds the cost near
// 1 % of the run even for files three times that, and a killed run's file lacks at most 1 s of
// rows (a checkpoint's rows are in checkpoint.bin, and write_summary writes them all).
inline constexpr std::chrono::milliseconds kSeriesRewritePeriod{1000};

// Where frames are formatted and written: on RunOutput's background thread (runs), or in the
// calling thread (tests compare the two).
enum class FrameWriting { background, in_caller };

class RunOutput {
 public:
  RunOutput(std::filesystem::path directory, FrameFormats formats, std::vector<std::string> series_columns,
            FrameWriting writing = FrameWriting::background);
  // Waits for the frame in flight. A failure of it can no longer be reported here: call
  // flush() (write_summary does) before the end of a run.
  ~RunOutput();
  RunOutput(const RunOutput&) = delete;
  RunOutput& operator=(const RunOutput&) = delete;

  // Creates the folder, checks it is writable, removes a previous run's files from it
  // (frames, series.csv, run.json, the indexes, checkpoint.bin, temporary files of those),
  // and nothing else.
  void prepare();
  // For a resumed run, after restore_state: checks that the folder is writable and removes
  // the frames that the restored bookkeeping does not list (written after the checkpoint
  // by a run that was killed, or the extra frame of an interruption) and temporary files.
  void prepare_resume();
  // Copies the frame and hands it to the writer (first waiting for the previous frame, if
  // it is still being written); the files and indexes appear when it is written.
  void write_frame(const ParticleSet& particles, const std::vector<FieldSpec>& fields, double time, long long step,
                   const std::string& title);
  // Waits until every frame handed over is on disk.
  void flush();
  void add_series_row(const std::vector<double>& values);  // one value per column
  // Rewrites series.csv atomically with every row so far, if a row came since it was last written.
  void write_series();
  // write_series() when kSeriesRewritePeriod of wall time has passed since the last rewrite (or
  // none was made): the file is rewritten whole, so a rewrite after every row cost O(rows^2)
  // (89-90 % of a 23,000-step run with a row per step, 2026-11-29). write_summary() always writes
  // it, so the file is complete whenever run.json is written (a checkpoint, the run's end, a stop).
  void write_series_when_due();
  // The period write_series_when_due() keeps (kSeriesRewritePeriod unless set; tests set it).
  void set_series_rewrite_period(std::chrono::milliseconds period) { series_rewrite_period_ = period; }
  void write_summary(const nlohmann::json& summary);  // series.csv and run.json, after flush()

  // Checkpoints: the series rows so far and the frames written (core/io/checkpoint.hpp).
  // save_state flushes first, so that a checkpoint lists only frames that are on disk.
  void save_state(CheckpointWriter& out);
  void restore_state(CheckpointReader& in);

  const std::filesystem::path& directory() const { return directory_; }
  long long last_frame_step() const { return frames_.empty() ? -1 : frames_.back().step; }
  std::size_t frames_written() const { return frames_.size(); }

  // A frame handed to the writer: its step and simulated time (s).
  struct FrameRecord {
    long long step = 0;
    double time = 0.0;
  };

 private:
  // The writing thread, the two frame buffers and the hand-over (defined in output.cpp).
  struct FrameWriter;

  // Throws the background writer's first failure, if there was one (it stays reported).
  void rethrow_write_failure();

  std::filesystem::path directory_;
  FrameFormats formats_;
  std::vector<std::string> series_columns_;
  std::string series_text_;
  bool series_unwritten_ = true;  // rows added (or restored) since series.csv was last written
  std::chrono::steady_clock::time_point series_written_at_{};
  std::chrono::milliseconds series_rewrite_period_ = kSeriesRewritePeriod;
  std::vector<FrameRecord> frames_;  // every frame handed over, in order (the indexes list them)
  std::unique_ptr<FrameWriter> writer_;
};

}  // namespace mps_lab
