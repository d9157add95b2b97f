/***************************************************************************
  projection.cpp - ground <-> pixel for an oriented image
 ***************************************************************************/
#include "geometry/projection.h"

#include <cmath>
#include <stdexcept>

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
      result.pixelInImage = mScanAffine ? scanFromNominal( projection.pixelInImage ) : projection.pixelInImage;
      result.inFrame = mCamera.isInFrame( result.pixelInImage );
    }
    return result;
  }

  void OrientedImage::setScanAffine( const Eigen::Matrix<double, 2, 3> &nominalFromScan )
  {
    const Eigen::Matrix2d linear = nominalFromScan.leftCols<2>();
    if ( !( std::abs( linear.determinant() ) > 1e-12 ) )
      throw std::invalid_argument( "the scan affine is singular" );
    mScanAffine = true;
    mNominalFromScan = nominalFromScan;
    const Eigen::Matrix2d inverse = linear.inverse();
    mScanFromNominal.leftCols<2>() = inverse;
    mScanFromNominal.col( 2 ) = -inverse * nominalFromScan.col( 2 );
  }

  Eigen::Vector2d OrientedImage::nominalFromScan( const Eigen::Vector2d &pixelInScan ) const
  {
    return mScanAffine ? Eigen::Vector2d( mNominalFromScan.leftCols<2>() * pixelInScan + mNominalFromScan.col( 2 ) ) : pixelInScan;
  }

  Eigen::Vector2d OrientedImage::scanFromNominal( const Eigen::Vector2d &nominalPixel ) const
  {
    return mScanAffine ? Eigen::Vector2d( mScanFromNominal.leftCols<2>() * nominalPixel + mScanFromNominal.col( 2 ) ) : nominalPixel;
  }

  OrientedImage OrientedImage::withExterior( const ExteriorOrientation &exterior ) const
  {
    OrientedImage other( mCamera, exterior );
    if ( mScanAffine )
      other.setScanAffine( mNominalFromScan );
    return other;
  }

  std::optional<Ray> OrientedImage::worldRayFromPixel( const Eigen::Vector2d &pixelInImage ) const
  {
    const std::optional<Eigen::Vector3d> rayInCamera = mCamera.rayInCameraFromPixel( nominalFromScan( pixelInImage ) );
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

  std::vector<Eigen::Vector3d> densifyForImage( const OrientedImage &image, const std::vector<Eigen::Vector3d> &vertices, double densifyPx,
      const std::function<std::optional<double>( const Eigen::Vector3d & )> &heightAt )
  {
    if ( !( densifyPx > 0.0 ) )
      throw std::invalid_argument( "densifyForImage: densifyPx must be positive" );
    std::vector<Eigen::Vector3d> out;
    // `depth`: halvings of a segment both of whose ends project; `towardsEdge`: halvings of one that leaves the
    // projectable space, which go on towards where it leaves it (20: a millionth of the segment), so that the
    // part that projects is densified up to there
    const std::function<void( const Eigen::Vector3d &, const GroundProjection &, const Eigen::Vector3d &, const GroundProjection &, int, int )> split =
      [&]( const Eigen::Vector3d & a, const GroundProjection & pa, const Eigen::Vector3d & b, const GroundProjection & pb, int depth, int towardsEdge )
    {
      const bool leaves = pa.ok() != pb.ok();
      if ( leaves ? towardsEdge >= 20 : ( depth >= 16 || !pa.ok() || ( pa.pixelInImage - pb.pixelInImage ).norm() <= densifyPx ) )
        return;
      Eigen::Vector3d mid = 0.5 * ( a + b );
      if ( heightAt )
        if ( const std::optional<double> h = heightAt( mid ) )
          mid.z() = *h;
      const GroundProjection pm = image.projectGroundToPixel( mid );
      const int nextDepth = leaves ? depth : depth + 1, nextEdge = leaves ? towardsEdge + 1 : towardsEdge;
      split( a, pa, mid, pm, nextDepth, nextEdge );
      out.push_back( mid );
      split( mid, pm, b, pb, nextDepth, nextEdge );
    };
    for ( size_t i = 0; i < vertices.size(); ++i )
    {
      out.push_back( vertices[i] );
      if ( i + 1 < vertices.size() )
        split( vertices[i], image.projectGroundToPixel( vertices[i] ), vertices[i + 1], image.projectGroundToPixel( vertices[i + 1] ), 0, 0 );
    }
    return out;
  }

  std::vector<Eigen::Vector3d> clipRingToImageField( const OrientedImage &image, const std::vector<Eigen::Vector3d> &ring, double nearM )
  {
    if ( !( nearM > 0 ) )
      throw std::invalid_argument( "clipRingToImageField: the near distance must be positive" );
    // half-spaces n . p + d <= 0 in the camera frame (the camera looks along -z)
    std::vector<std::pair<Eigen::Vector3d, double>> planes { { Eigen::Vector3d( 0, 0, 1 ), nearM } };
    const double field = image.camera().lensFieldRadius();
    if ( std::isfinite( field ) )
    {
      constexpr int kSides = 16;
      // the apothem of the inscribed polygon, a little inside so that points on it project
      const double apothem = 0.999 * field * std::cos( M_PI / kSides );
      for ( int k = 0; k < kSides; ++k )
      {
        const double theta = 2.0 * M_PI * k / kSides;
        // cos(t) xn + sin(t) yn <= apothem with xn = p.x / depth, yn = p.y / depth, depth = -p.z
        planes.push_back( { Eigen::Vector3d( std::cos( theta ), std::sin( theta ), apothem ), 0.0 } );
      }
    }
    std::vector<Eigen::Vector3d> polygon;
    for ( const Eigen::Vector3d &p : ring )
      polygon.push_back( image.cameraFromWorld( p ) );
    for ( const auto &[normal, offset] : planes )
    {
      if ( polygon.size() < 3 )
        return {};
      std::vector<Eigen::Vector3d> clipped;
      for ( size_t i = 0; i < polygon.size(); ++i )
      {
        const Eigen::Vector3d &a = polygon[i], &b = polygon[( i + 1 ) % polygon.size()];
        const double da = normal.dot( a ) + offset, db = normal.dot( b ) + offset;
        if ( da <= 0 )
          clipped.push_back( a );
        if ( ( da < 0 && db > 0 ) || ( da > 0 && db < 0 ) )
          clipped.push_back( a + ( da / ( da - db ) ) * ( b - a ) );
      }
      polygon = std::move( clipped );
    }
    if ( polygon.size() < 3 )
      return {};
    const Eigen::Matrix3d worldFromCamera = image.cameraFromWorldRotation().transpose();
    std::vector<Eigen::Vector3d> out;
    for ( const Eigen::Vector3d &p : polygon )
      out.push_back( image.exterior().projectionCentre + worldFromCamera * p );
    return out;
  }

} // namespace geostation
