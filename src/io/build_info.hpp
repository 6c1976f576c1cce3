#pragma once
// What the program was built from (cmake/build_info.cmake writes the definitions
// at every build), for summary.json and --version.

namespace vpc {

/// The project's version (CMakeLists.txt's project VERSION).
const char* version();
/// The git commit of the source tree at build time, with "-dirty" when tracked
/// files differed from it; "unknown" when the sources are not a git checkout.
const char* git_commit();

}  // namespace vpc
