/***************************************************************************
  colmapconversion.h - COLMAP cameras and poses to GeoStation's and back
  -------------------------------------------------------------------------
  Pixels: COLMAP puts the top-left corner of the image at (0, 0) and the
  centre of the first pixel at (0.5, 0.5), which is GeoStation's (and
  GDAL's) convention: principal points and observations carry over as they
  are.

  Lens models: COLMAP's SIMPLE_PINHOLE and PINHOLE are the model "none";
  SIMPLE_RADIAL (f, cx, cy, k), RADIAL (f, cx, cy, k1, k2), OPENCV (fx, fy,
  cx, cy, k1, k2, p1, p2) and FULL_OPENCV without its rational terms
  (k4 = k5 = k6 = 0) are exactly the model "opencv" (docs/conventions.md §2), whose
  formula COLMAP also uses. The fisheye models, FOV, THIN_PRISM_FISHEYE and
  FULL_OPENCV with a rational term cannot be represented and are refused by
  name.

  Poses: COLMAP stores camFromWorld (quaternion w, x, y, z and translation t)
  in the camera frame x right, y down, z forward. GeoStation's camera frame
  is x right, y up, z backwards (docs/conventions.md §3), so with D = diag(1, -1, -1)
      worldFromCamera = R_cw^T D,   projection centre = -R_cw^T t.
 ***************************************************************************/
#ifndef GEOSTATION_IO_COLMAPCONVERSION_H
#define GEOSTATION_IO_COLMAPCONVERSION_H

#include <string>

#include <Eigen/Core>

#include "camera/camera.h"
#include "geometry/exteriororientation.h"
#include "io/colmapmodel.h"

namespace geostation
{

  //! Why a camera cannot be carried between COLMAP and GeoStation.
  enum class CameraConversionStatus
  {
    Converted,
    Malformed,        //!< the camera is not well formed: its parameter count, a parameter not a number, its size, its focal length
    NotRepresentable, //!< the other side has no lens model that represents it exactly
  };

  //! A COLMAP camera as GeoStation's, or the sentence why not.
  struct CameraFromColmap
  {
    CameraConversionStatus status = CameraConversionStatus::Converted;
    std::string message; //!< one sentence naming the camera and what it has that GeoStation's lens models do not
    Camera camera;       //!< when Converted

    bool ok() const { return status == CameraConversionStatus::Converted; }
  };

  //! A GeoStation camera as COLMAP's, or the sentence why not.
  struct CameraToColmap
  {
    CameraConversionStatus status = CameraConversionStatus::Converted;
    std::string message; //!< one sentence naming the camera and its lens model
    ColmapCamera camera; //!< when Converted

    bool ok() const { return status == CameraConversionStatus::Converted; }
  };

  //! The GeoStation camera (id `cameraId`) of a COLMAP camera.
  CameraFromColmap cameraFromColmap( const ColmapCamera &colmapCamera, const std::string &cameraId );

  /**
   * The COLMAP camera of a GeoStation camera: SIMPLE_PINHOLE or PINHOLE for
   * "none", OPENCV (FULL_OPENCV when k3 is not 0) for "opencv";
   * NotRepresentable for "brown_photo", whose correction runs the other way
   * round.
   */
  CameraToColmap colmapCameraFromCamera( const Camera &camera, std::uint32_t colmapId );

  //! The exterior orientation of a COLMAP pose; throws std::invalid_argument for a zero or non-finite quaternion.
  ExteriorOrientation exteriorFromColmapPose( const Eigen::Vector4d &qvec, const Eigen::Vector3d &tvec );

  //! COLMAP's pose (qw >= 0) of an exterior orientation.
  void colmapPoseFromExterior( const ExteriorOrientation &exterior, Eigen::Vector4d *qvec, Eigen::Vector3d *tvec );

} // namespace geostation

#endif // GEOSTATION_IO_COLMAPCONVERSION_H
