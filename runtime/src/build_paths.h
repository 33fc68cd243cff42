#pragma once
// Folders fixed when the host was configured: the source tree, the install prefix's plugin and
// data folders, the build tree's plugin and web folders. They are compiled into one translation
// unit (build_paths.cpp), not passed to every file as macros, so that two checkouts of the same
// commit compile identical objects everywhere else and share the compiler cache.
#include <string>

namespace plugslam::runtime::build_paths {

/// The source tree this host was built from (configs/, ../shared/data beside it).
std::string sourceDir();
/// The install prefix's plugin folder.
std::string defaultPluginDir();
/// The build tree's plugin folder (used only when the host runs from that build tree).
std::string buildPluginDir();
/// The install prefix's data folder (share/plugslam: configs/, web/).
std::string installDataDir();
/// The build tree's bundled web page.
std::string buildWebDir();

}  // namespace plugslam::runtime::build_paths
