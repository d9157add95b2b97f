/***************************************************************************
  camera.h - interior orientation of a frame camera (docs/conventions.md §1-2)
  -------------------------------------------------------------------------
  Pixel coordinates are (col, row), continuous, origin at the top-left corner
  of the top-left pixel; the centre of pixel (i, j) is (i + 0.5, j + 0.5).

  The camera frame is the photogrammetric one: x right, y up, z backwards
  (the camera looks along -z). A point with camera coordinates p is in front
  of the camera when p.z < 0.
 ***************************************************************************/
#ifndef GEOSTATION_CAMERA_CAMERA_H
#define GEOSTATION_CAMERA_CAMERA_H

#include <array>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "camera/distortion.h"

namespace geostation
{

  enum class DistortionModel
  {
    None,       //!< no lens distortion
    OpenCV,     //!< OpenCV's projectPoints model on normalised coordinates
    BrownPhoto, //!< photogrammetric correction model on photo mm (thesis eq. 3.13)
  };

  //! The block-file name of a model: "none", "opencv" or "brown_photo".
  std::string distortionModelName( DistortionModel model );

  //! Parses a block-file model name; returns nothing for an unknown name.
  std::optional<DistortionModel> distortionModelFromName( const std::string &name );

  struct Distortion
  {
    DistortionModel model = DistortionModel::None;
    //! k1, k2, p1, p2, k3 (OpenCV's order; see distortion.h for units)
    std::array<double, kDistortionCoefficientCount> coeffs { 0, 0, 0, 0, 0 };

    double k1() const { return coeffs[0]; }
    double k2() const { return coeffs[1]; }
    double p1() const { return coeffs[2]; }
    double p2() const { return coeffs[3]; }
    double k3() const { return coeffs[4]; }
  };

  //! A fiducial mark of a film camera: calibrated photo coordinates (mm, x right, y up).
  struct Fiducial
  {
    std::string id;
    Eigen::Vector2d photoMm = Eigen::Vector2d::Zero();
  };

  //! Result of projecting a camera-frame point into the image.
  struct PixelProjection
  {
    enum class Status
    {
      Ok,                 //!< pixelInImage is valid (it may lie outside the frame)
      BehindCamera,       //!< p.z >= 0: the point is not in front of the camera
      DistortionDiverged, //!< the lens model could not be inverted there
      OutsideLensField,   //!< beyond the field where the lens model is valid (see Camera::lensFieldRadius)
    };
    Status status = Status::Ok;
    Eigen::Vector2d pixelInImage = Eigen::Vector2d::Zero();

    bool ok() const { return status == Status::Ok; }
  };

  /**
   * Interior orientation of one camera, in pixels.
   *
   * f is the principal distance in x-pixel units, aspect = fy / fx, (cx, cy)
   * the principal point in the pixel convention above. pixelSizeMm (x pixel
   * pitch) is required by the brown_photo model and by anything that reports
   * photo coordinates in mm.
   */
  class Camera
  {
    public:
      std::string id;
      int width = 0;  //!< image width in pixels
      int height = 0; //!< image height in pixels
      double f = 0.0; //!< principal distance, x-pixels
      double aspect = 1.0;
      double cx = 0.0; //!< principal point column, pixels
      double cy = 0.0; //!< principal point row, pixels
      std::optional<double> pixelSizeMm;
      Distortion distortion;
      std::vector<Fiducial> fiducials; //!< film cameras: calibrated fiducial marks

      double fx() const { return f; }
      double fy() const { return f * aspect; }

      //! Principal distance in mm; throws std::logic_error without pixelSizeMm.
      double principalDistanceMm() const;

      /**
       * Throws std::invalid_argument naming the first inconsistent value
       * (non-positive size, f or aspect; brown_photo without pixel size).
       */
      void validate() const;

      /**
       * Radius, in ideal normalised coordinates (tan of the off-axis angle),
       * within which the lens model is trusted: twice the radius of the frame
       * corner farthest from the principal point. A distortion polynomial is
       * calibrated on the frame; far beyond it, it is extrapolated and can
       * fold over, so points there are reported as OutsideLensField rather
       * than given a meaningless pixel. Infinite for the model "none".
       */
      double lensFieldRadius() const;

      //! True when the pixel lies on the frame [0, width) x [0, height).
      bool isInFrame( const Eigen::Vector2d &pixelInImage ) const;

      /**
       * Projects a point given in the camera frame to the image, applying lens
       * distortion. A point with p.z >= 0 is reported as BehindCamera and never
       * projected; one beyond lensFieldRadius() as OutsideLensField.
       */
      PixelProjection pixelFromCamera( const Eigen::Vector3d &pointInCamera ) const;

      /**
       * As pixelFromCamera(), with the lens field radius given, for callers
       * that project many points and compute lensFieldRadius() once.
       */
      PixelProjection pixelFromCamera( const Eigen::Vector3d &pointInCamera, double lensFieldRadius ) const;

      /**
       * The viewing ray of a pixel in the camera frame, scaled so that z = -1
       * (so x, y are ideal normalised coordinates with y up). Returns nothing
       * where the lens model cannot be inverted.
       */
      std::optional<Eigen::Vector3d> rayInCameraFromPixel( const Eigen::Vector2d &pixelInImage ) const;

      /**
       * d(col, row) / d(xn, yn) at a pixel, where (xn, yn) are the ideal
       * normalised coordinates of rayInCameraFromPixel() (y up). Adjustments
       * work on ideal coordinates and use this to weight and report in pixels.
       * Returns nothing where the lens model cannot be inverted.
       */
      std::optional<Eigen::Matrix2d> pixelJacobianWrtIdeal( const Eigen::Vector2d &pixelInImage ) const;
  };

} // namespace geostation

#endif // GEOSTATION_CAMERA_CAMERA_H
