#pragma once
// Errors that reach the user. Every message is one line that names the file, the key and
// what was expected; the front end prints it and exits non-zero.
#include <stdexcept>
#include <string>

namespace mps_lab {

// Bad input: a scene file, a --set override, a command-line value.
class InputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// The run could not write its output (unwritable folder, full disk).
class OutputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// "<source>: <key>: <message>"
[[noreturn]] void throw_input_error(const std::string& source, const std::string& key, const std::string& message);

}  // namespace mps_lab
