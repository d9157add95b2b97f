/***************************************************************************
  projection.h - ground <-> pixel for an oriented image (collinearity)
 ***************************************************************************/
#ifndef GEOSTATION_GEOMETRY_PROJECTION_H
#define GEOSTATION_GEOMETRY_PROJECTION_H

#include <functional>
#include <optional>
#include <vector>

#include <Eigen/Core>

#include "camera/camera.h"
#include "geometry/exteriororientation.h"

namespace geostation
{

  //! A ground point projected into one image.
  struct GroundProjection
  {
    PixelProjection::Status status = PixelProjection::Status::Ok;
    Eigen::Vector2d pixelInImage = Eigen::Vector2d::Zero(); //!< valid when ok()
    double depthM = 0.0;    //!< distance in front of the camera along its axis (-p.z), metres
    bool inFrame = false;   //!< projected and on [0, width) x [0, height)

    bool ok() const { return status == PixelProjection::Status::Ok; }
  };

  //! A viewing ray in object space: origin + t * direction, t >= 0.
  struct Ray
  {
    Eigen::Vector3d origin;    //!< the projection centre, block CRS metres
    Eigen::Vector3d direction; //!< unit vector
  };

  /**
   * One image's camera and exterior orientation, ready to project many points:
   * the rotation and the lens field are computed once. Holds a copy of both.
   */
  class OrientedImage
  {
    public:
      OrientedImage( const Camera &camera, const ExteriorOrientation &exterior );

      const Camera &camera() const { return mCamera; }
      const ExteriorOrientation &exterior() const { return mExterior; }

      //! R^T: object-space vectors to the camera frame.
      const Eigen::Matrix3d &cameraFromWorldRotation() const { return mCameraFromWorld; }

      //! p = R^T (P - X0)
      Eigen::Vector3d cameraFromWorld( const Eigen::Vector3d &pointInWorld ) const { return mCameraFromWorld * ( pointInWorld - mExterior.projectionCentre ); }

      //! Collinearity with distortion; see projectGroundToPixel().
      GroundProjection projectGroundToPixel( const Eigen::Vector3d &pointInWorld ) const;

      //! The viewing ray of a pixel; see worldRayFromPixel().
      std::optional<Ray> worldRayFromPixel( const Eigen::Vector2d &pixelInImage ) const;

      /**
       * Scanned film: the affine from the scan's pixels to the camera's
       * nominal pixels (where the camera model applies). Both directions of
       * projection then work in scan pixels. See Block::orientedImage().
       * Throws std::invalid_argument for a singular affine.
       */
      void setScanAffine( const Eigen::Matrix<double, 2, 3> &nominalFromScan );
      bool hasScanAffine() const { return mScanAffine; }
      Eigen::Vector2d nominalFromScan( const Eigen::Vector2d &pixelInScan ) const;
      Eigen::Vector2d scanFromNominal( const Eigen::Vector2d &nominalPixel ) const;

      //! The same image (camera, scan affine) with another exterior orientation.
      OrientedImage withExterior( const ExteriorOrientation &exterior ) const;

    private:
      Camera mCamera;
      ExteriorOrientation mExterior;
      Eigen::Matrix3d mCameraFromWorld;
      double mLensFieldRadius;
      bool mScanAffine = false;
      Eigen::Matrix<double, 2, 3> mNominalFromScan = Eigen::Matrix<double, 2, 3>::Identity();
      Eigen::Matrix<double, 2, 3> mScanFromNominal = Eigen::Matrix<double, 2, 3>::Identity();
  };

  /**
   * Collinearity with distortion: the pixel at which a ground point (block
   * CRS, metres) appears. Points behind the camera are reported as such.
   * For many points of one image, use OrientedImage.
   */
  GroundProjection projectGroundToPixel( const Camera &camera, const ExteriorOrientation &exterior, const Eigen::Vector3d &pointInWorld );

  /**
   * The viewing ray of a pixel in object space; nothing where the lens model
   * cannot be inverted.
   */
  std::optional<Ray> worldRayFromPixel( const Camera &camera, const ExteriorOrientation &exterior, const Eigen::Vector2d &pixelInImage );

  /**
   * A map polyline (block CRS, with heights) split until every piece projects
   * into the image no longer than `densifyPx` pixels, so a straight map
   * segment follows its curve in the photo. Inserted points take their
   * height from `heightAt` when it gives one (e.g. a DEM), otherwise the
   * linear interpolation. A segment that leaves the projectable space
   * (behind the camera, outside the lens field) is halved towards where it
   * leaves it, so its projectable part is densified up to there; pieces that
   * cannot be projected at all are not split. Throws std::invalid_argument
   * if densifyPx <= 0.
   */
  std::vector<Eigen::Vector3d> densifyForImage( const OrientedImage &image, const std::vector<Eigen::Vector3d> &vertices, double densifyPx,
      const std::function<std::optional<double>( const Eigen::Vector3d & )> &heightAt = nullptr );

  /**
   * A closed map ring (block CRS, first vertex not repeated) clipped to the
   * part of space the image can project: at least `nearM` in front of the
   * camera and inside the lens field (a 16-sided pyramid inscribed in the
   * field cone, so every point of the result projects). Sutherland-Hodgman,
   * plane by plane, in the camera frame; new vertices lie on the straight 3D
   * edges. Empty when nothing of the ring remains (fewer than 3 vertices).
   * Throws std::invalid_argument if nearM <= 0.
   */
  std::vector<Eigen::Vector3d> clipRingToImageField( const OrientedImage &image, const std::vector<Eigen::Vector3d> &ring, double nearM = 0.01 );

} // namespace geostation

#endif // GEOSTATION_GEOMETRY_PROJECTION_H
