#include "core/io/checkpoint.hpp"

#include <cstring>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "core/base/error.hpp"

namespace mps_lab {

namespace {

constexpr char kMagic[8] = {'M', 'P', 'S', 'L', 'A', 'B', 'C', 'K'};
constexpr std::uint32_t kByteOrderMark = 0x01020304;

template <typename T>
void append_value(std::string& out, const T& value) {
  char bytes[sizeof(T)];
  std::memcpy(bytes, &value, sizeof(T));
  out.append(bytes, sizeof(T));
}

void append_string(std::string& out, const std::string& text) {
  append_value(out, static_cast<std::uint64_t>(text.size()));
  out += text;
}

// FNV-1a, 64 bit: detects truncation and corruption (not an adversary).
std::uint64_t fnv1a(const char* data, std::size_t size) {
  std::uint64_t hash = 0xcbf29ce484222325ULL;
  for (std::size_t k = 0; k < size; ++k) {
    hash ^= static_cast<unsigned char>(data[k]);
    hash *= 0x100000001b3ULL;
  }
  return hash;
}

}  // namespace

// --- writer ---------------------------------------------------------------------------------

void CheckpointWriter::begin_section(const std::string& name) {
  if (open_) throw std::logic_error("checkpoint section '" + sections_.back().first + "' was not ended");
  for (const auto& section : sections_) {
    if (section.first == name) throw std::logic_error("checkpoint section '" + name + "' written twice");
  }
  sections_.emplace_back(name, std::string());
  open_ = true;
}

void CheckpointWriter::end_section() {
  if (!open_) throw std::logic_error("checkpoint: end_section without begin_section");
  open_ = false;
}

void CheckpointWriter::append_raw(const void* data, std::size_t bytes) {
  if (!open_) throw std::logic_error("checkpoint: a value written outside a section");
  if (bytes == 0) return;  // data() of an empty vector may be null
  sections_.back().second.append(static_cast<const char*>(data), bytes);
}

void CheckpointWriter::write_bool(bool value) {
  const std::uint8_t byte = value ? 1 : 0;
  append_raw(&byte, 1);
}
void CheckpointWriter::write_int(std::int64_t value) { append_raw(&value, sizeof value); }
void CheckpointWriter::write_size(std::size_t value) {
  const auto wide = static_cast<std::uint64_t>(value);
  append_raw(&wide, sizeof wide);
}
void CheckpointWriter::write_double(double value) { append_raw(&value, sizeof value); }
void CheckpointWriter::write_string(const std::string& text) {
  write_size(text.size());
  append_raw(text.data(), text.size());
}
void CheckpointWriter::write_doubles(const std::vector<double>& values) {
  write_size(values.size());
  append_raw(values.data(), values.size() * sizeof(double));
}
void CheckpointWriter::write_vec2s(const std::vector<Vec2>& values) {
  write_size(values.size());
  for (const auto& v : values) {
    write_double(v.x());
    write_double(v.y());
  }
}
void CheckpointWriter::write_u32s(const std::vector<std::uint32_t>& values) {
  write_size(values.size());
  append_raw(values.data(), values.size() * sizeof(std::uint32_t));
}
void CheckpointWriter::write_u8s(const std::vector<std::uint8_t>& values) {
  write_size(values.size());
  append_raw(values.data(), values.size());
}
void CheckpointWriter::write_chars(const std::vector<char>& values) {
  write_size(values.size());
  append_raw(values.data(), values.size());
}

std::string CheckpointWriter::file_content(const std::string& revision) const {
  if (open_) throw std::logic_error("checkpoint section '" + sections_.back().first + "' was not ended");
  std::string out(kMagic, sizeof kMagic);
  append_value(out, kCheckpointFormatVersion);
  append_value(out, kByteOrderMark);
  append_string(out, revision);
  append_value(out, static_cast<std::uint64_t>(sections_.size()));
  for (const auto& [name, payload] : sections_) {
    append_string(out, name);
    append_string(out, payload);
  }
  append_value(out, fnv1a(out.data(), out.size()));
  return out;
}

// --- reader ---------------------------------------------------------------------------------

CheckpointReader::CheckpointReader(std::string content, std::string source, const std::string& expected_revision)
    : content_(std::move(content)), source_(std::move(source)) {
  const auto broken = [this](const std::string& why) { throw_input_error(source_, "", why); };
  constexpr std::size_t header_bytes = sizeof kMagic + 2 * sizeof(std::uint32_t);
  if (content_.size() < sizeof kMagic || std::memcmp(content_.data(), kMagic, sizeof kMagic) != 0) {
    broken("not an mps_lab checkpoint (no MPSLABCK header)");
  }
  if (content_.size() < header_bytes + sizeof(std::uint64_t)) {
    broken("truncated checkpoint (" + std::to_string(content_.size()) + " bytes)");
  }
  std::uint32_t version = 0, byte_order = 0;
  std::memcpy(&version, content_.data() + sizeof kMagic, sizeof version);
  std::memcpy(&byte_order, content_.data() + sizeof kMagic + sizeof version, sizeof byte_order);
  if (byte_order != kByteOrderMark) broken("checkpoint written on a machine of another byte order");
  if (version != kCheckpointFormatVersion) {
    broken("checkpoint format " + std::to_string(version) + ", this build reads format " +
           std::to_string(kCheckpointFormatVersion));
  }
  const std::size_t body = content_.size() - sizeof(std::uint64_t);
  std::uint64_t stored_checksum = 0;
  std::memcpy(&stored_checksum, content_.data() + body, sizeof stored_checksum);
  if (fnv1a(content_.data(), body) != stored_checksum) {
    broken("truncated or corrupted checkpoint (checksum mismatch, " + std::to_string(content_.size()) + " bytes)");
  }

  // The framing, read as one pseudo-section spanning the header and the section table.
  section_ = "header";
  cursor_ = header_bytes;
  section_end_ = body;
  revision_ = read_string();
  if (revision_ != expected_revision) {
    broken("written by mps_lab " + revision_ + ", this is " + expected_revision +
           "; only the build that wrote a checkpoint continues it bit for bit");
  }
  const std::size_t count = read_size();
  for (std::size_t k = 0; k < count; ++k) {
    const std::string name = read_string();
    const std::size_t length = read_count(1);
    if (!sections_.emplace(name, std::make_pair(cursor_, length)).second) fail("section '" + name + "' twice");
    cursor_ += length;
  }
  if (cursor_ != body) fail(std::to_string(body - cursor_) + " bytes after the last section");
  section_.clear();
}

CheckpointReader CheckpointReader::from_file(const std::filesystem::path& path, const std::string& expected_revision) {
  std::ifstream file(path, std::ios::binary);
  if (!file) throw_input_error(path.string(), "", "cannot open the checkpoint");
  std::ostringstream content;
  content << file.rdbuf();
  return CheckpointReader(content.str(), path.string(), expected_revision);
}

void CheckpointReader::begin_section(const std::string& name) {
  if (!section_.empty()) throw std::logic_error("checkpoint section '" + section_ + "' was not ended");
  const auto found = sections_.find(name);
  if (found == sections_.end()) throw_input_error(source_, "", "no section '" + name + "' in the checkpoint");
  section_ = name;
  cursor_ = found->second.first;
  section_end_ = found->second.first + found->second.second;
}

void CheckpointReader::end_section() {
  if (cursor_ != section_end_) {
    fail(std::to_string(section_end_ - cursor_) + " bytes left unread (written by another layout)");
  }
  section_.clear();
}

void CheckpointReader::fail(const std::string& message) const {
  throw_input_error(source_, section_.empty() ? "" : "section '" + section_ + "'", message);
}

void CheckpointReader::read_raw(void* data, std::size_t bytes) {
  if (section_.empty()) throw std::logic_error("checkpoint: a value read outside a section");
  if (bytes > section_end_ - cursor_) fail("ends early (truncated, or written by another layout)");
  if (bytes == 0) return;  // data() of an empty vector may be null
  std::memcpy(data, content_.data() + cursor_, bytes);
  cursor_ += bytes;
}

std::size_t CheckpointReader::read_count(std::size_t element_bytes) {
  std::uint64_t count = 0;
  read_raw(&count, sizeof count);
  if (count > (section_end_ - cursor_) / element_bytes) fail("ends early (truncated, or written by another layout)");
  return static_cast<std::size_t>(count);
}

bool CheckpointReader::read_bool() {
  std::uint8_t byte = 0;
  read_raw(&byte, 1);
  if (byte > 1) fail("a boolean is " + std::to_string(byte));
  return byte == 1;
}
std::int64_t CheckpointReader::read_int() {
  std::int64_t value = 0;
  read_raw(&value, sizeof value);
  return value;
}
std::size_t CheckpointReader::read_size() {
  std::uint64_t value = 0;
  read_raw(&value, sizeof value);
  return static_cast<std::size_t>(value);
}
double CheckpointReader::read_double() {
  double value = 0.0;
  read_raw(&value, sizeof value);
  return value;
}
std::string CheckpointReader::read_string() {
  std::string text(read_count(1), '\0');
  read_raw(text.data(), text.size());
  return text;
}
std::vector<double> CheckpointReader::read_doubles() {
  std::vector<double> values(read_count(sizeof(double)));
  read_raw(values.data(), values.size() * sizeof(double));
  return values;
}
std::vector<Vec2> CheckpointReader::read_vec2s() {
  std::vector<Vec2> values(read_count(2 * sizeof(double)));
  for (auto& v : values) {
    v.x() = read_double();
    v.y() = read_double();
  }
  return values;
}
std::vector<std::uint32_t> CheckpointReader::read_u32s() {
  std::vector<std::uint32_t> values(read_count(sizeof(std::uint32_t)));
  read_raw(values.data(), values.size() * sizeof(std::uint32_t));
  return values;
}
std::vector<std::uint8_t> CheckpointReader::read_u8s() {
  std::vector<std::uint8_t> values(read_count(1));
  read_raw(values.data(), values.size());
  return values;
}
std::vector<char> CheckpointReader::read_chars() {
  std::vector<char> values(read_count(1));
  read_raw(values.data(), values.size());
  return values;
}

// --- shared pieces --------------------------------------------------------------------------

void write_particles(CheckpointWriter& writer, const ParticleSet& particles) {
  writer.write_vec2s(particles.position);
  writer.write_vec2s(particles.velocity);
  writer.write_doubles(particles.pressure);
  std::vector<std::uint8_t> types(particles.size());
  for (std::size_t i = 0; i < particles.size(); ++i) types[i] = static_cast<std::uint8_t>(particles.type[i]);
  writer.write_u8s(types);
  writer.write_u8s(particles.wall_layer);
  writer.write_u32s(particles.id);  // the order in memory (cell-ordered particles)
  writer.write_size(particles.scalar_fields.size());
  for (const auto& [name, values] : particles.scalar_fields) {
    writer.write_string(name);
    writer.write_doubles(values);
  }
}

void read_particles(CheckpointReader& reader, ParticleSet& particles) {
  const std::size_t n = particles.size();
  const auto check_size = [&](std::size_t size, const char* what) {
    if (size != n) {
      reader.fail(std::string(what) + " of " + std::to_string(size) + " particles, the scene has " + std::to_string(n));
    }
  };
  particles.position = reader.read_vec2s();
  check_size(particles.position.size(), "positions");
  particles.velocity = reader.read_vec2s();
  check_size(particles.velocity.size(), "velocities");
  particles.pressure = reader.read_doubles();
  check_size(particles.pressure.size(), "pressures");
  const std::vector<std::uint8_t> types = reader.read_u8s();
  check_size(types.size(), "types");
  for (std::size_t i = 0; i < n; ++i) {
    if (types[i] > static_cast<std::uint8_t>(ParticleType::Ghost))
      reader.fail("particle type " + std::to_string(types[i]));
    particles.type[i] = static_cast<ParticleType>(types[i]);
  }
  particles.wall_layer = reader.read_u8s();
  check_size(particles.wall_layer.size(), "wall layers");
  particles.id = reader.read_u32s();
  check_size(particles.id.size(), "ids");
  try {
    (void)ParticleOrder::from_old_indices(particles.id);  // the ids are a permutation of 0..N-1
  } catch (const std::logic_error&) {
    reader.fail("particle ids that are not a permutation of 0.." + std::to_string(n - 1));
  }
  const std::size_t fields = reader.read_size();
  if (fields != particles.scalar_fields.size()) {
    reader.fail(std::to_string(fields) + " particle fields, the method declares " +
                std::to_string(particles.scalar_fields.size()));
  }
  for (std::size_t k = 0; k < fields; ++k) {
    const std::string name = reader.read_string();
    const auto found = particles.scalar_fields.find(name);
    if (found == particles.scalar_fields.end())
      reader.fail("particle field '" + name + "' is not declared by the method");
    found->second = reader.read_doubles();
    check_size(found->second.size(), ("field '" + name + "'").c_str());
  }
}

void write_neighbour_list(CheckpointWriter& writer, const NeighbourList& list) {
  writer.write_u32s(list.offsets);
  writer.write_u32s(list.indices);
  writer.write_double(list.radius);
}

void read_neighbour_list(CheckpointReader& reader, NeighbourList& list) {
  list.offsets = reader.read_u32s();
  list.indices = reader.read_u32s();
  list.radius = reader.read_double();
  const bool consistent = list.offsets.empty()
                              ? list.indices.empty()
                              : list.offsets.front() == 0 && list.offsets.back() == list.indices.size();
  if (!consistent) reader.fail("an inconsistent neighbour list");
}

// Doubles per wall sample: position 2, velocity map 4, volume 1, wall velocity 2, wall acceleration 2.
constexpr std::size_t kWallSampleValues = 11;

void write_wall_samples(CheckpointWriter& writer, const WallSampleList& samples) {
  writer.write_u32s(samples.offsets);
  std::vector<double> values;
  std::vector<std::uint32_t> sources, obstacles;
  values.reserve(samples.samples.size() * kWallSampleValues);
  for (const WallSample& sample : samples.samples) {
    values.insert(values.end(),
                  {sample.position.x(), sample.position.y(), sample.velocity_map(0, 0), sample.velocity_map(0, 1),
                   sample.velocity_map(1, 0), sample.velocity_map(1, 1), sample.volume, sample.wall_velocity.x(),
                   sample.wall_velocity.y(), sample.wall_acceleration.x(), sample.wall_acceleration.y()});
    sources.push_back(sample.source);
    obstacles.push_back(static_cast<std::uint32_t>(sample.obstacle));  // -1 as 0xffffffff
  }
  writer.write_doubles(values);
  writer.write_u32s(sources);
  writer.write_u32s(obstacles);
}

void read_wall_samples(CheckpointReader& reader, WallSampleList& samples) {
  samples.offsets = reader.read_u32s();
  const std::vector<double> values = reader.read_doubles();
  const std::vector<std::uint32_t> sources = reader.read_u32s();
  const std::vector<std::uint32_t> obstacles = reader.read_u32s();
  const bool consistent =
      values.size() == kWallSampleValues * sources.size() && obstacles.size() == sources.size() &&
      (samples.offsets.empty() ? sources.empty()
                               : samples.offsets.front() == 0 && samples.offsets.back() == sources.size());
  if (!consistent) reader.fail("inconsistent wall samples");
  samples.samples.resize(sources.size());
  for (std::size_t k = 0; k < sources.size(); ++k) {
    const double* v = &values[kWallSampleValues * k];
    WallSample& sample = samples.samples[k];
    sample.position = Vec2(v[0], v[1]);
    sample.velocity_map << v[2], v[3], v[4], v[5];
    sample.volume = v[6];
    sample.wall_velocity = Vec2(v[7], v[8]);
    sample.wall_acceleration = Vec2(v[9], v[10]);
    sample.source = sources[k];
    sample.obstacle = static_cast<std::int32_t>(obstacles[k]);
  }
}

}  // namespace mps_lab
