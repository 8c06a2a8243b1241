#pragma once
// Declared parameters. A method or a wall treatment declares every parameter it reads
// (name, type, default, range, unit, one-line description); the scene loader checks a
// parameter block against the declaration (unknown keys and out-of-range values are
// errors naming the key) and resolves defaults. ParameterValues remembers which values
// were read, so a declared-but-ignored parameter is caught (see check_all_read).
#include <limits>
#include <map>
#include <set>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/base/types.hpp"

namespace mps_lab {

enum class ParameterKind { Number, Integer, Boolean, String, Vector2, StringList };

struct ParameterSpec {
  std::string name;
  ParameterKind kind = ParameterKind::Number;
  nlohmann::json default_value;
  std::string unit;         // "" for dimensionless; "m", "s", "Pa", "l0" (multiples of the spacing)
  std::string description;  // one line, shown by `mps_lab methods --parameters`
  double minimum = -std::numeric_limits<double>::infinity();
  double maximum = std::numeric_limits<double>::infinity();
  bool minimum_exclusive = false;
  bool maximum_exclusive = false;
  std::vector<std::string> choices;  // allowed values of a String / StringList (empty: any)
  bool required = false;             // no default: the scene must give it

  // Builder helpers, so that declarations read as one line each.
  ParameterSpec& at_least(double value) {
    minimum = value;
    minimum_exclusive = false;
    return *this;
  }
  ParameterSpec& above(double value) {
    minimum = value;
    minimum_exclusive = true;
    return *this;
  }
  ParameterSpec& at_most(double value) {
    maximum = value;
    maximum_exclusive = false;
    return *this;
  }
  ParameterSpec& below(double value) {
    maximum = value;
    maximum_exclusive = true;
    return *this;
  }
  ParameterSpec& one_of(std::vector<std::string> values) {
    choices = std::move(values);
    return *this;
  }
  ParameterSpec& mandatory() {
    required = true;
    return *this;
  }

  std::string range_text() const;  // e.g. "a number > 0", "an integer in [1, 100000]"
};

ParameterSpec number_parameter(std::string name, double default_value, std::string unit, std::string description);
ParameterSpec integer_parameter(std::string name, long long default_value, std::string description);
ParameterSpec boolean_parameter(std::string name, bool default_value, std::string description);
ParameterSpec string_parameter(std::string name, std::string default_value, std::string description);
ParameterSpec vector2_parameter(std::string name, Vec2 default_value, std::string unit, std::string description);
ParameterSpec string_list_parameter(std::string name, std::vector<std::string> default_value, std::string description);

class ParameterValues {
 public:
  ParameterValues() = default;
  ParameterValues(std::map<std::string, nlohmann::json> values, std::string block_path);

  double number(const std::string& name) const;
  long long integer(const std::string& name) const;
  bool boolean(const std::string& name) const;
  const std::string& string(const std::string& name) const;
  Vec2 vector2(const std::string& name) const;
  std::vector<std::string> string_list(const std::string& name) const;
  bool contains(const std::string& name) const { return values_.count(name) != 0; }

  // Every resolved value (defaults included), for run.json.
  nlohmann::json to_json() const;
  const std::string& block_path() const { return block_path_; }
  // Declared parameters nobody read: a plugin that declares a parameter must use it.
  std::vector<std::string> unread() const;

 private:
  const nlohmann::json& get(const std::string& name) const;
  std::map<std::string, nlohmann::json> values_;
  std::string block_path_;
  mutable std::set<std::string> read_;
};

// Checks `block` (a JSON object, may be null = all defaults) against `specs`.
// `source` is the scene file, `block_path` the dotted path of the block, both for messages.
// Keys listed in `reserved_keys` are skipped (sub-blocks handled by the caller).
ParameterValues resolve_parameters(const std::vector<ParameterSpec>& specs, const nlohmann::json& block,
                                   const std::string& source, const std::string& block_path,
                                   const std::set<std::string>& reserved_keys = {});

// Throws std::logic_error naming the plugin and the parameters it declared but never read.
void check_all_read(const ParameterValues& values, const std::string& plugin);

// A short description of a JSON value's type, for error messages ("a string", "an array").
std::string json_type_name(const nlohmann::json& value);

// A JSON value as error messages quote it: one line, at most 80 characters (longer values
// and deep nesting are cut with "..."), invalid UTF-8 replaced.
std::string describe_json(const nlohmann::json& value);

}  // namespace mps_lab
