/***************************************************************************
  runtrack.cpp - the run a line is traced through (runtrack.h)
 ***************************************************************************/
#include "tracing/runtrack.h"

#include <stdexcept>

#include "tracing/rigroles.h"
#include "tracing/trackgeometry.h"

namespace geostation
{

  RunTrack::RunTrack( const Block &block, const BlockImage &seedImage, double cameraHeightM )
    : mSequence( block )
    , mSeedStation( seedStationIndex( mSequence, seedImage ) )
    , mReferenceImages( imagesInRole( block, mSequence, mSeedStation, seedImage ) )
    , mTrajectory( referenceTrajectory() )
    , mSmoothTrack( smoothedHeights( mTrajectory, 30.0 ) )
    , mCameraHeightM( cameraHeightM )
  {
  }

  int RunTrack::seedStationIndex( const StationSequence &sequence, const BlockImage &seedImage )
  {
    if ( !seedImage.exterior )
      throw std::invalid_argument( "the seed image " + seedImage.id + " is not oriented" );
    const int k = sequence.indexOf( seedImage.stationId.empty() ? seedImage.id : seedImage.stationId );
    if ( k < 0 )
      throw std::invalid_argument( "the seed image " + seedImage.id + " belongs to no station of the block" );
    return k;
  }

  const BlockImage *RunTrack::referenceImageAt( int stationIndex ) const
  {
    if ( stationIndex < 0 || stationIndex >= static_cast<int>( mReferenceImages.size() ) )
      return nullptr;
    const BlockImage *image = mReferenceImages[stationIndex];
    return image && image->exterior ? image : nullptr;
  }

  std::vector<Eigen::Vector3d> RunTrack::referenceTrajectory() const
  {
    std::vector<Eigen::Vector3d> trajectory;
    for ( int k = 0; k < mSequence.size(); ++k )
      if ( const BlockImage *image = referenceImageAt( k ) )
      {
        const Eigen::Vector3d &c = image->exterior->projectionCentre;
        if ( trajectory.size() >= 2 && ( c - trajectory.back() ).head<2>().dot( ( trajectory.back() - trajectory[trajectory.size() - 2] ).head<2>() ) <= 0 )
          continue;
        trajectory.push_back( c );
      }
    return trajectory;
  }

  std::optional<double> RunTrack::surfaceHeight( const Eigen::Vector2d &xy, double cameraZ, const Eigen::Vector2d &cameraXY ) const
  {
    const std::optional<double> here = trackSurfaceHeight( mSmoothTrack, xy, mCameraHeightM ), under = trackSurfaceHeight( mSmoothTrack, cameraXY, 0.0 );
    if ( !here || !under )
      return std::nullopt;
    return *here + ( cameraZ - *under );
  }

  GroundOfPixel RunTrack::roadPlaneOf( double cameraZ, const Eigen::Vector2d &cameraXY ) const
  {
    return [this, cameraZ, cameraXY]( const OrientedImage &image, const Eigen::Vector2d &pixel ) -> std::optional<Eigen::Vector3d>
    {
      std::optional<Eigen::Vector3d> p = roadPlanePoint( image, pixel, cameraZ - mCameraHeightM );
      for ( int it = 0; it < 2 && p; ++it )
        if ( const std::optional<double> surface = surfaceHeight( p->head<2>(), cameraZ, cameraXY ) )
          if ( std::optional<Eigen::Vector3d> q = roadPlanePoint( image, pixel, *surface ) )
            p = q;
      return p;
    };
  }

} // namespace geostation
