/***************************************************************************
  projection.cpp - ground <-> pixel for an oriented image
 ***************************************************************************/
#include "geometry/projection.h"

#include <Eigen/Geometry>

namespace geostation
{

  GroundProjection projectGroundToPixel( const Camera &camera, const ExteriorOrientation &exterior, const Eigen::Vector3d &pointInWorld )
  {
    const Eigen::Vector3d pointInCamera = exterior.cameraFromWorld( pointInWorld );
    const PixelProjection projection = camera.pixelFromCamera( pointInCamera );
    GroundProjection result;
    result.status = projection.status;
    result.depthM = -pointInCamera.z();
    if ( projection.ok() )
    {
      result.pixelInImage = projection.pixelInImage;
      result.inFrame = camera.isInFrame( projection.pixelInImage );
    }
    return result;
  }

  std::optional<Ray> worldRayFromPixel( const Camera &camera, const ExteriorOrientation &exterior, const Eigen::Vector2d &pixelInImage )
  {
    const std::optional<Eigen::Vector3d> rayInCamera = camera.rayInCameraFromPixel( pixelInImage );
    if ( !rayInCamera )
      return std::nullopt;
    return Ray { exterior.projectionCentre, exterior.worldDirectionFromCamera( *rayInCamera ).normalized() };
  }

} // namespace geostation
