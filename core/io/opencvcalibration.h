/***************************************************************************
  opencvcalibration.h - cameras from OpenCV calibration files, with their
                        mounting on a mapping van
  -------------------------------------------------------------------------
  An OpenCV calibration file (cv::FileStorage YAML or XML, as OpenCV's
  calibration sample writes it) holds camera_matrix, distortion_coefficients,
  image_width and image_height. For a rig of several cameras the file holds
  a sequence "cameras" of such maps, each with an "id" and the camera's
  mounting on the vehicle:
    lever_arm      [x, y, z] metres from the trajectory's reference point to
                   the projection centre, in the body frame (x forward,
                   y right, z down)
    boresight      [roll, pitch, heading] degrees of the camera in the body
                   frame; all 0: the camera looks forward along body x with
                   image right = body y (right) and image up = body -z (up)
    image_pattern  the image file of a trajectory row, e.g.
                   "images/{station}_front.jpg" ({station}, {row}, {time})

  OpenCV's pixel centres are integers: cx = cx_cv + 0.5, cy = cy_cv + 0.5
  (docs/conventions.md §2). The distortion (k1, k2, p1, p2[, k3[, k4, k5, k6...]])
  is the model "opencv"; rational, thin-prism or tilt terms that are not 0
  cannot be represented and are refused, as is a camera matrix with skew.
 ***************************************************************************/
#ifndef GEOSTATION_IO_OPENCVCALIBRATION_H
#define GEOSTATION_IO_OPENCVCALIBRATION_H

#include <filesystem>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "camera/camera.h"

namespace geostation
{

  struct RigCamera
  {
    Camera camera;
    Eigen::Vector3d leverArmM = Eigen::Vector3d::Zero();    //!< body frame (x forward, y right, z down), metres
    Eigen::Vector3d boresightDeg = Eigen::Vector3d::Zero(); //!< roll, pitch, heading in the body frame, degrees
    std::string imagePattern;                               //!< empty: image names come from the trajectory table
  };

  /**
   * Reads the cameras of an OpenCV calibration file (YAML, YML or XML). A
   * single-camera file gets the id of the file's stem. Throws
   * std::invalid_argument with one sentence naming the file and the key.
   */
  std::vector<RigCamera> readOpenCvCalibration( const std::filesystem::path &file );

  /**
   * A camera from OpenCV's camera matrix (3 x 3, no skew), distortion
   * coefficients (4, 5, 8, 12 or 14 values) and image size. Throws
   * std::invalid_argument naming what cannot be represented.
   */
  Camera cameraFromOpenCv( const std::string &id, const Eigen::Matrix3d &cameraMatrix, const std::vector<double> &distortion, int width, int height );

  //! True when the file looks like an OpenCV calibration (a readable FileStorage with camera_matrix or cameras).
  bool isOpenCvCalibration( const std::filesystem::path &file );

} // namespace geostation

#endif // GEOSTATION_IO_OPENCVCALIBRATION_H
