#include "build_paths.h"

namespace plugslam::runtime::build_paths {

std::string sourceDir() { return PLUGSLAM_SOURCE_DIR; }
std::string defaultPluginDir() { return PLUGSLAM_DEFAULT_PLUGIN_DIR; }
std::string buildPluginDir() { return PLUGSLAM_BUILD_PLUGIN_DIR; }
std::string installDataDir() { return PLUGSLAM_INSTALL_DATADIR; }
std::string buildWebDir() { return PLUGSLAM_BUILD_WEB_DIR; }

}  // namespace plugslam::runtime::build_paths
