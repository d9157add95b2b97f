/***************************************************************************
  epipolar.cpp - epipolar curves between two oriented images
 ***************************************************************************/
#include "geometry/epipolar.h"

#include <cmath>
#include <limits>
#include <stdexcept>

#include "geometry/polyline.h"

namespace geostation
{

  namespace
  {
    struct Sample
    {
      double distanceM;
      GroundProjection projection;
    };

    Sample sampleAt( const Ray &ray, const OrientedImage &to, double distanceM )
    {
      return { distanceM, to.projectGroundToPixel( ray.origin + distanceM * ray.direction ) };
    }

    //! Whether the segment's bounding box touches the frame grown by its own size on every side.
    bool nearFrame( const Camera &camera, const Eigen::Vector2d &a, const Eigen::Vector2d &b )
    {
      const double w = camera.width, h = camera.height;
      return std::max( a.x(), b.x() ) >= -w && std::min( a.x(), b.x() ) <= 2 * w
             && std::max( a.y(), b.y() ) >= -h && std::min( a.y(), b.y() ) <= 2 * h;
    }
  } // namespace

  size_t EpipolarCurve::vertexCount() const
  {
    size_t count = 0;
    for ( const auto &piece : pieces )
      count += piece.size();
    return count;
  }

  double EpipolarCurve::distanceToCurvePx( const Eigen::Vector2d &pixel, double *distanceAlongRayM ) const
  {
    double best = std::numeric_limits<double>::infinity();
    for ( const auto &piece : pieces )
    {
      for ( size_t i = 0; i < piece.size(); ++i )
      {
        const Eigen::Vector2d a = piece[i].pixelInImage;
        const Eigen::Vector2d b = i + 1 < piece.size() ? piece[i + 1].pixelInImage : a;
        const double t = nearestOnSegment( a, b, pixel );
        const double d = ( a + t * ( b - a ) - pixel ).norm();
        if ( d < best )
        {
          best = d;
          if ( distanceAlongRayM )
          {
            const double d1 = i + 1 < piece.size() ? piece[i + 1].distanceM : piece[i].distanceM;
            *distanceAlongRayM = piece[i].distanceM + t * ( d1 - piece[i].distanceM );
          }
        }
      }
    }
    return best;
  }

  EpipolarCurve epipolarCurve( const OrientedImage &from, const Eigen::Vector2d &pixelInFrom, const OrientedImage &to, const EpipolarOptions &options )
  {
    if ( !( options.minDistanceM > 0.0 ) || !( options.maxDistanceM > options.minDistanceM ) || !( options.maxSegmentPx > 0.0 ) )
      throw std::invalid_argument( "epipolarCurve: needs 0 < minDistanceM < maxDistanceM and maxSegmentPx > 0" );

    EpipolarCurve curve;
    const std::optional<Ray> ray = from.worldRayFromPixel( pixelInFrom );
    if ( !ray )
      return curve;

    // Coarse samples uniform in inverse distance (uniform in image space for a
    // pinhole), then refine each gap by bisection until it is short enough.
    const int coarse = 64;
    std::vector<Sample> samples;
    const double inverseNear = 1.0 / options.minDistanceM, inverseFar = 1.0 / options.maxDistanceM;
    for ( int k = 0; k <= coarse; ++k )
      samples.push_back( sampleAt( *ray, to, 1.0 / ( inverseNear + ( inverseFar - inverseNear ) * k / coarse ) ) );

    std::vector<Sample> refined;
    refined.push_back( samples.front() );
    for ( size_t k = 1; k < samples.size(); ++k )
    {
      // Depth-first bisection of the gap (samples[k-1], samples[k]).
      std::vector<Sample> stack { samples[k] };
      while ( !stack.empty() )
      {
        const Sample &a = refined.back();
        const Sample b = stack.back();
        // Over the budget nothing more is refined, but nothing is dropped either.
        const bool mayRefine = static_cast<int>( refined.size() + stack.size() ) < options.maxVertices;
        const bool bothOk = a.projection.ok() && b.projection.ok();
        // Far from the frame (towards the epipole the curve runs off to
        // infinity) a long segment is harmless and is not refined.
        const bool tooLong = mayRefine && bothOk && ( b.projection.pixelInImage - a.projection.pixelInImage ).norm() > options.maxSegmentPx
                             && nearFrame( to.camera(), a.projection.pixelInImage, b.projection.pixelInImage );
        // A gap between a projectable and an unprojectable sample is bisected
        // too, so the piece ends close to where the curve really ends.
        const bool boundary = mayRefine && a.projection.ok() != b.projection.ok() && std::abs( b.distanceM - a.distanceM ) > 1e-3 * a.distanceM;
        if ( tooLong || boundary )
        {
          const double mid = 2.0 / ( 1.0 / a.distanceM + 1.0 / b.distanceM );
          if ( std::abs( mid - a.distanceM ) < 1e-9 * a.distanceM )
          {
            refined.push_back( b );
            stack.pop_back();
            continue;
          }
          stack.push_back( sampleAt( *ray, to, mid ) );
        }
        else
        {
          refined.push_back( b );
          stack.pop_back();
        }
      }
    }

    std::vector<EpipolarVertex> piece;
    for ( const Sample &s : refined )
    {
      if ( s.projection.ok() )
        piece.push_back( { s.projection.pixelInImage, s.distanceM, s.projection.inFrame } );
      else if ( !piece.empty() )
      {
        curve.pieces.push_back( std::move( piece ) );
        piece.clear();
      }
    }
    if ( !piece.empty() )
      curve.pieces.push_back( std::move( piece ) );
    return curve;
  }

} // namespace geostation
