#include "core/base/parameters.hpp"

#include <cmath>
#include <cstdio>
#include <sstream>

#include "core/base/error.hpp"

namespace mps_lab {

namespace {

std::string format_number(double value) {
  std::ostringstream out;
  out << value;
  return out.str();
}

std::string join(const std::vector<std::string>& items) {
  std::string text;
  for (const auto& item : items) {
    if (!text.empty()) text += ", ";
    text += item;
  }
  return text;
}

// Bytes of the UTF-8 character starting at text[at], or 0 if none starts there.
std::size_t utf8_length(const std::string& text, std::size_t at) {
  const auto lead = static_cast<unsigned char>(text[at]);
  std::size_t length = 0;
  if (lead < 0x80) {
    length = 1;
  } else if (lead >= 0xC2 && lead <= 0xDF) {
    length = 2;
  } else if (lead >= 0xE0 && lead <= 0xEF) {
    length = 3;
  } else if (lead >= 0xF0 && lead <= 0xF4) {
    length = 4;
  }
  if (length == 0 || at + length > text.size()) return 0;
  for (std::size_t k = 1; k < length; ++k) {
    if ((static_cast<unsigned char>(text[at + k]) & 0xC0) != 0x80) return 0;
  }
  return length;
}

// Control characters (a newline in a key or a file name) escaped and bytes that are not
// UTF-8 replaced by '?', so that a message stays one printable line whatever the input held.
std::string one_line(const std::string& text) {
  std::string out;
  out.reserve(text.size());
  for (std::size_t at = 0; at < text.size();) {
    const auto byte = static_cast<unsigned char>(text[at]);
    const std::size_t length = utf8_length(text, at);
    if (length > 1 || (length == 1 && byte >= 0x20 && byte != 0x7f)) {
      out.append(text, at, length);
      at += length;
      continue;
    }
    if (length == 0) {
      out += '?';
    } else if (byte == '\n') {
      out += "\\n";
    } else {
      char escaped[8];
      std::snprintf(escaped, sizeof escaped, "\\x%02x", byte);
      out += escaped;
    }
    ++at;
  }
  return out;
}

constexpr std::size_t kLongestDescription = 80;  // characters of a value quoted in a message

void append_description(std::string& out, const nlohmann::json& value, int depth) {
  if (out.size() > kLongestDescription) return;  // the rest is cut anyway
  if (value.is_array() || value.is_object()) {
    const bool array = value.is_array();
    if (value.empty()) {
      out += array ? "[]" : "{}";
      return;
    }
    if (depth >= 3) {
      out += array ? "[...]" : "{...}";
      return;
    }
    out += array ? '[' : '{';
    bool first = true;
    for (auto item = value.begin(); item != value.end() && out.size() <= kLongestDescription; ++item) {
      if (!first) out += ',';
      first = false;
      if (!array)
        out += nlohmann::json(item.key()).dump(-1, ' ', false, nlohmann::json::error_handler_t::replace) + ':';
      append_description(out, *item, depth + 1);
    }
    out += array ? ']' : '}';
    return;
  }
  if (value.is_string() && value.get_ref<const std::string&>().size() > kLongestDescription) {
    const nlohmann::json start = value.get_ref<const std::string&>().substr(0, kLongestDescription);
    out += start.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
    return;
  }
  out += value.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
}

}  // namespace

void throw_input_error(const std::string& source, const std::string& key, const std::string& message) {
  std::string text = source;
  if (!key.empty()) text += (text.empty() ? "" : ": ") + key;
  throw InputError(one_line(text + ": " + message));
}

std::string describe_json(const nlohmann::json& value) {
  std::string out;
  append_description(out, value, 0);
  if (out.size() > kLongestDescription) {
    std::size_t cut = kLongestDescription - 3;
    while (cut > 0 && (static_cast<unsigned char>(out[cut]) & 0xC0) == 0x80) --cut;  // not inside a UTF-8 character
    out.resize(cut);
    out += "...";
  }
  return out;
}

std::string json_type_name(const nlohmann::json& value) {
  switch (value.type()) {
    case nlohmann::json::value_t::null:
      return "null";
    case nlohmann::json::value_t::object:
      return "an object";
    case nlohmann::json::value_t::array:
      return "an array";
    case nlohmann::json::value_t::string:
      return "a string";
    case nlohmann::json::value_t::boolean:
      return "a boolean";
    case nlohmann::json::value_t::number_integer:
    case nlohmann::json::value_t::number_unsigned:
      return "an integer";
    case nlohmann::json::value_t::number_float:
      return "a number";
    default:
      return "an unsupported value";
  }
}

std::string ParameterSpec::range_text() const {
  std::string kind_text;
  switch (kind) {
    case ParameterKind::Number:
      kind_text = "a number";
      break;
    case ParameterKind::Integer:
      kind_text = "an integer";
      break;
    case ParameterKind::Boolean:
      return "true or false";
    case ParameterKind::String:
      return choices.empty() ? "a string" : "one of: " + join(choices);
    case ParameterKind::Vector2:
      return "an array of two finite numbers [x, y]";
    case ParameterKind::StringList:
      return choices.empty() ? "an array of strings" : "an array of strings from: " + join(choices);
  }
  const bool has_min = std::isfinite(minimum);
  const bool has_max = std::isfinite(maximum);
  if (has_min && has_max) {
    return kind_text + " in " + (minimum_exclusive ? "(" : "[") + format_number(minimum) + ", " +
           format_number(maximum) + (maximum_exclusive ? ")" : "]");
  }
  if (has_min) return kind_text + (minimum_exclusive ? " > " : " >= ") + format_number(minimum);
  if (has_max) return kind_text + (maximum_exclusive ? " < " : " <= ") + format_number(maximum);
  return kind_text;
}

ParameterSpec number_parameter(std::string name, double default_value, std::string unit, std::string description) {
  ParameterSpec spec;
  spec.name = std::move(name);
  spec.kind = ParameterKind::Number;
  spec.default_value = default_value;
  spec.unit = std::move(unit);
  spec.description = std::move(description);
  return spec;
}

ParameterSpec integer_parameter(std::string name, long long default_value, std::string description) {
  ParameterSpec spec;
  spec.name = std::move(name);
  spec.kind = ParameterKind::Integer;
  spec.default_value = default_value;
  spec.description = std::move(description);
  return spec;
}

ParameterSpec boolean_parameter(std::string name, bool default_value, std::string description) {
  ParameterSpec spec;
  spec.name = std::move(name);
  spec.kind = ParameterKind::Boolean;
  spec.default_value = default_value;
  spec.description = std::move(description);
  return spec;
}

ParameterSpec string_parameter(std::string name, std::string default_value, std::string description) {
  ParameterSpec spec;
  spec.name = std::move(name);
  spec.kind = ParameterKind::String;
  spec.default_value = std::move(default_value);
  spec.description = std::move(description);
  return spec;
}

ParameterSpec vector2_parameter(std::string name, Vec2 default_value, std::string unit, std::string description) {
  ParameterSpec spec;
  spec.name = std::move(name);
  spec.kind = ParameterKind::Vector2;
  spec.default_value = nlohmann::json::array({default_value.x(), default_value.y()});
  spec.unit = std::move(unit);
  spec.description = std::move(description);
  return spec;
}

ParameterSpec string_list_parameter(std::string name, std::vector<std::string> default_value, std::string description) {
  ParameterSpec spec;
  spec.name = std::move(name);
  spec.kind = ParameterKind::StringList;
  spec.default_value = default_value;
  spec.description = std::move(description);
  return spec;
}

ParameterValues::ParameterValues(std::map<std::string, nlohmann::json> values, std::string block_path)
    : values_(std::move(values)), block_path_(std::move(block_path)) {}

const nlohmann::json& ParameterValues::get(const std::string& name) const {
  auto found = values_.find(name);
  if (found == values_.end()) {
    throw std::logic_error("parameter '" + name + "' is not declared in " + block_path_);
  }
  read_.insert(name);
  return found->second;
}

double ParameterValues::number(const std::string& name) const { return get(name).get<double>(); }
long long ParameterValues::integer(const std::string& name) const { return get(name).get<long long>(); }
bool ParameterValues::boolean(const std::string& name) const { return get(name).get<bool>(); }
const std::string& ParameterValues::string(const std::string& name) const {
  return get(name).get_ref<const std::string&>();
}

Vec2 ParameterValues::vector2(const std::string& name) const {
  const auto& value = get(name);
  return Vec2(value.at(0).get<double>(), value.at(1).get<double>());
}

std::vector<std::string> ParameterValues::string_list(const std::string& name) const {
  return get(name).get<std::vector<std::string>>();
}

nlohmann::json ParameterValues::to_json() const {
  nlohmann::json out = nlohmann::json::object();
  for (const auto& [name, value] : values_) out[name] = value;
  return out;
}

std::vector<std::string> ParameterValues::unread() const {
  std::vector<std::string> names;
  for (const auto& [name, value] : values_) {
    if (read_.count(name) == 0) names.push_back(name);
  }
  return names;
}

void check_all_read(const ParameterValues& values, const std::string& plugin) {
  const auto unread = values.unread();
  if (!unread.empty()) {
    throw std::logic_error(plugin + " declares parameters it never reads: " + join(unread) +
                           " (a parsed-but-ignored option is a bug)");
  }
}

namespace {

nlohmann::json check_value(const ParameterSpec& spec, const nlohmann::json& value, const std::string& source,
                           const std::string& key) {
  const std::string expected = "expected " + spec.range_text();
  switch (spec.kind) {
    case ParameterKind::Boolean:
      if (!value.is_boolean()) throw_input_error(source, key, "got " + describe_json(value) + ", " + expected);
      return value;
    case ParameterKind::String: {
      if (!value.is_string()) throw_input_error(source, key, "got " + describe_json(value) + ", " + expected);
      if (!spec.choices.empty()) {
        const auto& text = value.get_ref<const std::string&>();
        bool known = false;
        for (const auto& choice : spec.choices) known = known || choice == text;
        if (!known) throw_input_error(source, key, "got " + describe_json(value) + ", " + expected);
      }
      return value;
    }
    case ParameterKind::Vector2: {
      bool ok = value.is_array() && value.size() == 2;
      for (std::size_t k = 0; ok && k < 2; ++k) {
        ok = value[k].is_number() && std::isfinite(value[k].get<double>());
      }
      if (!ok) throw_input_error(source, key, "got " + describe_json(value) + ", " + expected);
      return nlohmann::json::array({value[0].get<double>(), value[1].get<double>()});
    }
    case ParameterKind::StringList: {
      bool ok = value.is_array();
      for (std::size_t k = 0; ok && k < value.size(); ++k) {
        ok = value[k].is_string();
        if (ok && !spec.choices.empty()) {
          bool known = false;
          for (const auto& choice : spec.choices) known = known || choice == value[k].get<std::string>();
          ok = known;
        }
      }
      if (!ok) throw_input_error(source, key, "got " + describe_json(value) + ", " + expected);
      return value;
    }
    case ParameterKind::Integer:
    case ParameterKind::Number: {
      if (!value.is_number()) throw_input_error(source, key, "got " + describe_json(value) + ", " + expected);
      const double number = value.get<double>();
      if (!std::isfinite(number)) throw_input_error(source, key, "got " + describe_json(value) + ", " + expected);
      if (spec.kind == ParameterKind::Integer && (std::floor(number) != number || std::fabs(number) > 9e15)) {
        throw_input_error(source, key, "got " + describe_json(value) + ", " + expected);
      }
      const bool below_min = spec.minimum_exclusive ? !(number > spec.minimum) : !(number >= spec.minimum);
      const bool above_max = spec.maximum_exclusive ? !(number < spec.maximum) : !(number <= spec.maximum);
      if (below_min || above_max) throw_input_error(source, key, "got " + describe_json(value) + ", " + expected);
      if (spec.kind == ParameterKind::Integer) return nlohmann::json(static_cast<long long>(number));
      return nlohmann::json(number);
    }
  }
  return value;
}

}  // namespace

ParameterValues resolve_parameters(const std::vector<ParameterSpec>& specs, const nlohmann::json& block,
                                   const std::string& source, const std::string& block_path,
                                   const std::set<std::string>& reserved_keys) {
  if (!block.is_null() && !block.is_object()) {
    throw_input_error(source, block_path, "got " + describe_json(block) + ", expected an object");
  }
  const auto key_path = [&](const std::string& name) { return block_path.empty() ? name : block_path + "." + name; };
  if (block.is_object()) {
    for (const auto& [key, value] : block.items()) {
      if (reserved_keys.count(key) != 0) continue;
      bool declared = false;
      for (const auto& spec : specs) declared = declared || spec.name == key;
      if (!declared) {
        std::vector<std::string> known;
        for (const auto& spec : specs) known.push_back(spec.name);
        for (const auto& reserved : reserved_keys) known.push_back(reserved);
        throw_input_error(source, key_path(key),
                          "unknown key (expected one of: " + (known.empty() ? "none" : join(known)) + ")");
      }
    }
  }
  std::map<std::string, nlohmann::json> values;
  for (const auto& spec : specs) {
    if (block.is_object() && block.contains(spec.name)) {
      values[spec.name] = check_value(spec, block.at(spec.name), source, key_path(spec.name));
    } else {
      if (spec.required) throw_input_error(source, key_path(spec.name), "missing; expected " + spec.range_text());
      values[spec.name] = spec.default_value;
    }
  }
  return ParameterValues(std::move(values), block_path);
}

}  // namespace mps_lab
