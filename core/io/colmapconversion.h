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

#include <optional>
#include <string>

#include <Eigen/Core>

#include "camera/camera.h"
#include "geometry/exteriororientation.h"
#include "io/colmapmodel.h"

namespace geostation
{

  /**
   * The GeoStation camera of a COLMAP camera, or nothing with `*whyNot` set
   * to a sentence naming the model and what it has that GeoStation's lens
   * models do not.
   */
  std::optional<Camera> cameraFromColmap( const ColmapCamera &colmapCamera, const std::string &cameraId, std::string *whyNot );

  /**
   * The COLMAP camera of a GeoStation camera: SIMPLE_PINHOLE or PINHOLE for
   * "none", OPENCV (FULL_OPENCV when k3 is not 0) for "opencv"; nothing for
   * "brown_photo", whose correction runs the other way round, and for film
   * cameras with a scan affine, with `*whyNot` set.
   */
  std::optional<ColmapCamera> colmapCameraFromCamera( const Camera &camera, std::uint32_t colmapId, std::string *whyNot );

  //! The exterior orientation of a COLMAP pose; throws std::invalid_argument for a zero or non-finite quaternion.
  ExteriorOrientation exteriorFromColmapPose( const Eigen::Vector4d &qvec, const Eigen::Vector3d &tvec );

  //! COLMAP's pose (qw >= 0) of an exterior orientation.
  void colmapPoseFromExterior( const ExteriorOrientation &exterior, Eigen::Vector4d *qvec, Eigen::Vector3d *tvec );

} // namespace geostation

#endif // GEOSTATION_IO_COLMAPCONVERSION_H
