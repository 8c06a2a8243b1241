#pragma once
// Where the testbed's data lives: the experimental data (analysis/validation/), the analysis
// scripts (analysis/) and the scenes (scenes/). A binary run from its build folder uses the
// source tree it was built from; an installed one (`cmake --install build --prefix P`) uses
// P/share/mps_lab, found beside the executable (P/bin/mps_lab).
#include <string>

namespace mps_lab {

// The folder that holds analysis/ and scenes/: <prefix>/share/mps_lab when this executable is
// installed there, else the source tree (MPS_LAB_SOURCE_DIR).
std::string data_directory();

// "mps_lab <version> (git <revision>)".
std::string version_line();

}  // namespace mps_lab
