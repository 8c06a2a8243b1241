#pragma once
// Checkpoints: the whole state of a run in one compact binary file, from which
// `mps_lab resume` continues bit for bit (docs/checkpoints.md).
//
// File layout. Integers and doubles are stored in the byte order of the machine that wrote
// the file (the header records it); a double is its 8 bytes, so it reads back bit-exact.
//   "MPSLABCK"              8 bytes, the magic
//   u32 format version      kCheckpointFormatVersion (the layout of this header and framing)
//   u32 byte-order mark     0x01020304 as written
//   string git revision     the build that wrote it; only the same build may resume
//   u64 section count
//   sections                string name, u64 payload length, payload
//   u64 checksum            FNV-1a (64 bit) of every byte before it
// A string is a u64 length and its bytes; an array is a u64 count and its elements.
//
// Sections are named and length-prefixed and a reader looks them up by name, so adding state
// means adding a section: no offsets move, and a missing or half-read section is a clear
// error instead of garbage. Every error of the reader is an InputError whose one line names
// the file (and the section).
#include <cstdint>
#include <filesystem>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "core/base/particles.hpp"
#include "core/base/types.hpp"
#include "core/search/neighbour_search.hpp"
#include "core/walls/wall_samples.hpp"

namespace mps_lab {

constexpr std::uint32_t kCheckpointFormatVersion = 1;

class CheckpointWriter {
 public:
  // Sections are written one after the other; every value belongs to the open section.
  void begin_section(const std::string& name);
  void end_section();

  void write_bool(bool value);
  void write_int(std::int64_t value);
  void write_size(std::size_t value);
  void write_double(double value);
  void write_string(const std::string& text);
  void write_doubles(const std::vector<double>& values);
  void write_vec2s(const std::vector<Vec2>& values);
  void write_u32s(const std::vector<std::uint32_t>& values);
  void write_u8s(const std::vector<std::uint8_t>& values);
  void write_chars(const std::vector<char>& values);

  // The complete file: header (with `revision`), the sections, the checksum.
  std::string file_content(const std::string& revision) const;

 private:
  void append_raw(const void* data, std::size_t bytes);
  std::vector<std::pair<std::string, std::string>> sections_;  // (name, payload)
  bool open_ = false;
};

class CheckpointReader {
 public:
  // Parses and checks `content`, read from `source` (a file name, for messages): magic,
  // format version, byte order, checksum, framing, and that `expected_revision` wrote it.
  CheckpointReader(std::string content, std::string source, const std::string& expected_revision);

  // Reads the whole file (InputError if it cannot be opened).
  static CheckpointReader from_file(const std::filesystem::path& path, const std::string& expected_revision);

  const std::string& source() const { return source_; }
  const std::string& revision() const { return revision_; }
  bool has_section(const std::string& name) const { return sections_.count(name) > 0; }

  // Opens a section (InputError if absent); end_section() checks that it was read to its end.
  void begin_section(const std::string& name);
  void end_section();

  bool read_bool();
  std::int64_t read_int();
  std::size_t read_size();
  double read_double();
  std::string read_string();
  std::vector<double> read_doubles();
  std::vector<Vec2> read_vec2s();
  std::vector<std::uint32_t> read_u32s();
  std::vector<std::uint8_t> read_u8s();
  std::vector<char> read_chars();

  // An InputError "<file>: section '<name>': <message>", for checks of the values read.
  [[noreturn]] void fail(const std::string& message) const;

 private:
  void read_raw(void* data, std::size_t bytes);
  std::size_t read_count(std::size_t element_bytes);

  std::string content_;
  std::string source_;
  std::string revision_;
  std::map<std::string, std::pair<std::size_t, std::size_t>> sections_;  // name -> (offset, length)
  std::string section_;                                                  // the open section, "" if none
  std::size_t cursor_ = 0;                                               // offset in content_
  std::size_t section_end_ = 0;
};

// Every array of a ParticleSet, named scalar fields included. read_particles fills a set
// built from the same scene (same particle count and fields), else fails naming the file.
void write_particles(CheckpointWriter& writer, const ParticleSet& particles);
void read_particles(CheckpointReader& reader, ParticleSet& particles);

// A neighbour list (offsets, indices, radius), for methods that keep one between steps.
void write_neighbour_list(CheckpointWriter& writer, const NeighbourList& list);
void read_neighbour_list(CheckpointReader& reader, NeighbourList& list);

// The wall samples of a boundary model (core/walls/wall_samples.hpp), for methods that keep them
// with their neighbour list between steps.
void write_wall_samples(CheckpointWriter& writer, const WallSampleList& samples);
void read_wall_samples(CheckpointReader& reader, WallSampleList& samples);

}  // namespace mps_lab
