#include "lab/data_directory.hpp"

#include <filesystem>
#include <system_error>

#include "core/run/driver.hpp"

namespace mps_lab {

namespace {

// The installed layout relative to the executable: bin/mps_lab -> share/mps_lab/.
std::filesystem::path installed_data_directory() {
  std::error_code error;
  const auto executable = std::filesystem::read_symlink("/proc/self/exe", error);
  if (error) return {};
  return executable.parent_path().parent_path() / "share" / "mps_lab";
}

}  // namespace

std::string data_directory() {
  const auto installed = installed_data_directory();
  std::error_code error;
  if (!installed.empty() && std::filesystem::is_directory(installed / "analysis", error)) return installed.string();
  return MPS_LAB_SOURCE_DIR;
}

std::string version_line() { return std::string("mps_lab ") + MPS_LAB_VERSION + " (git " + git_revision() + ")"; }

}  // namespace mps_lab
