#pragma once
// The files of the EuRoC MAV (ASL) layout: mav0/camN/data.csv, mav0/camN/sensor.yaml and the
// ground truth csv (state_groundtruth_estimate0/data.csv, or the 8-column rows ORB-SLAM3 ships).
#include <Eigen/Geometry>
#include <cstdint>
#include <string>
#include <vector>

#include "plugslam/sensor_data.h"
#include "plugslam/trajectory.h"

namespace plugslam {
namespace io {

/// One row of a camN/data.csv: the capture time and the image's file name under camN/data/.
struct EurocImage {
  std::int64_t stamp_ns = 0;  ///< EuRoC clock [ns]
  std::string file;           ///< file name relative to camN/data/
  int line = 0;               ///< 1-based line in data.csv
};

/// camN/data.csv ("#timestamp [ns],filename" header, then "t,name" rows); ParseError for a
/// malformed row or a timestamp that does not increase.
std::vector<EurocImage> parseEurocImageList(const std::string& text, const std::string& file);

/// A camera's sensor.yaml: intrinsics with distortion, and T_BS (camera in the body frame).
struct EurocCamera {
  CameraIntrinsics intrinsics;                             ///< pinhole, size, distortion
  Eigen::Isometry3d T_BS = Eigen::Isometry3d::Identity();  ///< camera pose in the body frame
};

/// Parses a sensor.yaml (OpenCV's "%YAML:1.0" first line accepted). ParseError naming the file
/// and the key when T_BS, resolution, intrinsics, distortion_model or distortion_coefficients is
/// missing or malformed, the camera model is not pinhole, or T_BS is not rigid.
EurocCamera parseEurocSensor(const std::string& text, const std::string& file);

/// Ground truth rows "t [ns], px, py, pz, qw, qx, qy, qz[, ...]" (EuRoC's body pose in its
/// world); further columns (velocities, biases) are ignored. Times in seconds.
Trajectory parseEurocGroundTruth(const std::string& text, const std::string& file);

}  // namespace io
}  // namespace plugslam
