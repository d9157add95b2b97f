/***************************************************************************
  demintersection.cpp - the first intersection of a ray with a DEM
 ***************************************************************************/
#include "dem/demintersection.h"

#include <cmath>

namespace geostation
{

  DemIntersection intersectRayWithDem( const Ray &ray, const Dem &dem, const CrsTransform &blockToDem, const DemIntersectionOptions &options )
  {
    DemIntersection result;
    const Eigen::Vector3d d = ray.direction.normalized();
    const double dxy = d.head<2>().norm(), dz = std::abs( d.z() );

    // Cell size in metres: the unit of the smallest step.
    const std::array<double, 6> &gt = dem.geoTransform();
    const Eigen::Vector3d startInDem = blockToDem.transform( ray.origin );
    const Eigen::Vector2d perUnit = dem.metresPerUnit( startInDem.x(), startInDem.y() );
    const double cellM = std::min( std::hypot( gt[1], gt[4] ) * perUnit.x(), std::hypot( gt[2], gt[5] ) * perUnit.y() );
    // Near the surface the slope-bounded steps shrink geometrically; below a
    // quarter cell, fixed quarter-cell steps with a sign test take over (two
    // crossings closer together than that are taken as one).
    const double minStep = std::max( 0.25 * cellM, options.toleranceM );
    // The slope bound holds over the tiles around a point: steps stay shorter than a tile.
    const double maxStep = std::min( 64, dem.tileSize() ) * cellM;

    struct Sample
    {
      bool defined;
      double h; //!< ray height above the surface
      bool inside; //!< within the DEM's cell-centre area
      double slope;
    };
    const auto sampleAt = [&]( double t ) -> Sample
    {
      const Eigen::Vector3d p = ray.origin + t * d;
      const Eigen::Vector3d q = blockToDem.transform( p );
      const Dem::Sample at = dem.sample( q.x(), q.y() );
      // Heights are compared in the block CRS's vertical (CONVENTIONS §4).
      return { at.height.has_value(), at.height ? p.z() - *at.height : 0.0, at.covers, at.slopeBound };
    };

    double t = 0.0;
    Sample s = sampleAt( t );
    bool entered = s.defined;
    if ( entered && s.h <= 0.0 )
    {
      result.status = DemIntersection::Status::BelowSurface;
      result.message = "the ray starts below the terrain (is the camera height in the DEM's vertical datum?)";
      return result;
    }
    for ( ; t <= options.maxRangeM; ++result.steps )
    {
      double step;
      if ( !s.defined )
      {
        if ( s.inside )
        {
          result.status = DemIntersection::Status::Hole;
          result.message = "the ray meets a hole in the DEM too large to fill";
          return result;
        }
        if ( entered )
        {
          result.status = DemIntersection::Status::Miss;
          result.message = "the ray leaves the DEM without meeting it";
          return result;
        }
        step = cellM; // not yet over the DEM: walk in until it starts
      }
      else
      {
        const double rate = dz + s.slope * dxy;
        step = std::min( rate > 0.0 ? std::max( s.h / rate, minStep ) : maxStep, maxStep );
      }
      double tNext = t + step;
      Sample next = sampleAt( tNext );
      // Stepping off the DEM (or into a hole) from over it: shorten the step
      // down to the tolerance, so a crossing just before the edge is not lost.
      while ( s.defined && !next.defined && step > options.toleranceM )
      {
        step = std::max( 0.5 * step, options.toleranceM );
        tNext = t + step;
        next = sampleAt( tNext );
      }
      if ( next.defined && next.h <= 0.0 && s.defined )
      {
        // Bracketed: Illinois false position on the bilinear surface (exact in
        // one step where h is linear along the ray), bisection as a fallback.
        double lo = t, hi = tNext, hLo = s.h, hHi = next.h;
        int side = 0;
        double root = 0.5 * ( lo + hi );
        for ( int iteration = 0; iteration < 100 && hi - lo > options.toleranceM; ++iteration )
        {
          root = hLo - hHi > 0.0 ? lo + ( hi - lo ) * hLo / ( hLo - hHi ) : 0.5 * ( lo + hi );
          if ( !( root > lo && root < hi ) )
            root = 0.5 * ( lo + hi );
          const Sample m = sampleAt( root );
          if ( !m.defined )
            break;
          if ( std::abs( m.h ) < 0.1 * options.toleranceM )
          {
            lo = hi = root;
            break;
          }
          if ( m.h > 0.0 )
          {
            lo = root;
            hLo = m.h;
            if ( side == +1 )
              hHi *= 0.5;
            side = +1;
          }
          else
          {
            hi = root;
            hHi = m.h;
            if ( side == -1 )
              hLo *= 0.5;
            side = -1;
          }
        }
        result.status = DemIntersection::Status::Hit;
        result.rangeM = 0.5 * ( lo + hi );
        result.point = ray.origin + result.rangeM * d;
        return result;
      }
      if ( next.defined && !entered )
      {
        entered = true;
        if ( next.h <= 0.0 )
        {
          // Entered the DEM's area already below its surface: the crossing is at its edge.
          result.status = DemIntersection::Status::Miss;
          result.message = "the ray enters the DEM's area below its surface";
          return result;
        }
      }
      t = tNext;
      s = next;
    }
    result.status = DemIntersection::Status::Miss;
    result.message = "the ray does not meet the DEM within " + std::to_string( static_cast<long>( options.maxRangeM ) ) + " m";
    return result;
  }

} // namespace geostation
