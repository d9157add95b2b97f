/***************************************************************************
  projection.cpp - ground <-> pixel for an oriented image
 ***************************************************************************/
#include "geometry/projection.h"

#include <Eigen/Geometry>

namespace geostation
{

  OrientedImage::OrientedImage( const Camera &camera, const ExteriorOrientation &exterior )
    : mCamera( camera )
    , mExterior( exterior )
    , mCameraFromWorld( exterior.worldFromCamera().transpose() )
    , mLensFieldRadius( camera.lensFieldRadius() )
  {}

  GroundProjection OrientedImage::projectGroundToPixel( const Eigen::Vector3d &pointInWorld ) const
  {
    const Eigen::Vector3d pointInCamera = cameraFromWorld( pointInWorld );
    const PixelProjection projection = mCamera.pixelFromCamera( pointInCamera, mLensFieldRadius );
    GroundProjection result;
    result.status = projection.status;
    result.depthM = -pointInCamera.z();
    if ( projection.ok() )
    {
      result.pixelInImage = projection.pixelInImage;
      result.inFrame = mCamera.isInFrame( projection.pixelInImage );
    }
    return result;
  }

  std::optional<Ray> OrientedImage::worldRayFromPixel( const Eigen::Vector2d &pixelInImage ) const
  {
    const std::optional<Eigen::Vector3d> rayInCamera = mCamera.rayInCameraFromPixel( pixelInImage );
    if ( !rayInCamera )
      return std::nullopt;
    return Ray { mExterior.projectionCentre, ( mCameraFromWorld.transpose() * *rayInCamera ).normalized() };
  }

  GroundProjection projectGroundToPixel( const Camera &camera, const ExteriorOrientation &exterior, const Eigen::Vector3d &pointInWorld )
  {
    return OrientedImage( camera, exterior ).projectGroundToPixel( pointInWorld );
  }

  std::optional<Ray> worldRayFromPixel( const Camera &camera, const ExteriorOrientation &exterior, const Eigen::Vector2d &pixelInImage )
  {
    return OrientedImage( camera, exterior ).worldRayFromPixel( pixelInImage );
  }

} // namespace geostation
