/***************************************************************************
  demintersection.cpp - the first intersection of a ray with a DEM
 ***************************************************************************/
#include "dem/demintersection.h"

#include "dem/gridwalk.h"

#include <cmath>
#include <limits>

namespace geostation
{

  using namespace gridwalk;

  namespace
  {

    void setBelowAtEntry( DemIntersection &result, bool atStart )
    {
      result.status = atStart ? DemIntersection::Status::BelowSurface : DemIntersection::Status::Miss;
      result.message = atStart ? "the ray starts below the terrain (is the camera height in the DEM's vertical datum?)"
                       : "the ray enters the DEM's area below its surface";
    }

    void setHit( DemIntersection &result, const Ray &ray, const Eigen::Vector3d &d, double t )
    {
      result.status = DemIntersection::Status::Hit;
      result.rangeM = t;
      result.point = ray.origin + t * d;
    }

    /**
     * The crossing of heightAbove(t) (NaN where undefined) near `guess`, not
     * before `entry`: bracketed by widening steps, then false position
     * (Illinois) to `tolerance`; the guess if no bracket is found.
     */
    template <class HeightAbove>
    double refineOnCurve( const HeightAbove &heightAbove, double guess, double entry, double tolerance )
    {
      double lo = std::max( entry, guess - 1e-3 ), hi = guess + 1e-3;
      double hLo = heightAbove( lo ), hHi = heightAbove( hi );
      for ( int widen = 0; widen < 20 && !( hLo > 0.0 && hHi <= 0.0 ); ++widen )
      {
        if ( !( hLo > 0.0 ) && lo > entry )
          hLo = heightAbove( lo = std::max( entry, lo - 4.0 * ( hi - lo ) ) );
        if ( !( hHi <= 0.0 ) )
          hHi = heightAbove( hi = hi + 4.0 * ( hi - lo ) );
      }
      if ( !( hLo > 0.0 && hHi <= 0.0 ) )
        return guess;
      int side = 0;
      for ( int iteration = 0; iteration < 100 && hi - lo > tolerance; ++iteration )
      {
        double root = lo + ( hi - lo ) * hLo / ( hLo - hHi );
        if ( !( root > lo && root < hi ) )
          root = 0.5 * ( lo + hi );
        const double h = heightAbove( root );
        if ( std::isnan( h ) )
          break;
        if ( h > 0.0 )
        {
          lo = root;
          hLo = h;
          if ( side == +1 )
            hHi *= 0.5;
          side = +1;
        }
        else
        {
          hi = root;
          hHi = h;
          if ( side == -1 )
            hLo *= 0.5;
          side = -1;
        }
      }
      return 0.5 * ( lo + hi );
    }

    void setHole( DemIntersection &result )
    {
      result.status = DemIntersection::Status::Hole;
      result.message = "the ray meets a hole in the DEM too large to fill";
    }


    //! A DEM in the block's own CRS: the ray is straight in its grid.
    DemIntersection intersectInGrid( const Ray &ray, const Eigen::Vector3d &d, const Dem &dem, const DemIntersectionOptions &options )
    {
      DemIntersection result;
      const GridRay g = chord( gridPoint( dem, ray.origin ), gridPoint( dem, ray.origin + d ), 0.0, 1.0, ray.origin.z(), d.z() );
      double t0 = 0.0, t1 = options.maxRangeM;
      bool exits = false;
      if ( !clipToDem( g, dem, t0, t1, exits ) )
      {
        result.message = "the ray does not pass over the DEM";
        return result;
      }
      const GridWalk walk = walkGrid( g, dem, t0, t1 );
      result.steps = walk.steps;
      if ( walk.hit && *walk.hit <= t0 )
        setBelowAtEntry( result, t0 == 0.0 );
      else if ( walk.hit )
        setHit( result, ray, d, *walk.hit );
      else if ( walk.hole )
        setHole( result );
      else
        result.message = exits ? "the ray leaves the DEM without meeting it"
                         : "the ray does not meet the DEM within " + std::to_string( static_cast<long>( options.maxRangeM ) ) + " m";
      return result;
    }

    /**
     * A DEM in another CRS: the ray is curved in its grid. It is followed
     * chord by chord (each straight in the grid, ends transformed exactly,
     * chords short enough to stay within 0.05 mm of the curve), and the
     * crossing found on a chord is refined on the exact curve.
     */
    DemIntersection intersectAlongChords( const Ray &ray, const Eigen::Vector3d &d, const Dem &dem, const CrsTransform &blockToDem, const DemIntersectionOptions &options )
    {
      DemIntersection result;
      const auto gridAt = [&]( double t ) { return gridPoint( dem, blockToDem.transform( ray.origin + t * d ) ); };
      // The exact height above the DEM at range t; NaN where it is undefined.
      const auto heightAbove = [&]( double t )
      {
        const Eigen::Vector3d p = ray.origin + t * d;
        const Eigen::Vector3d q = blockToDem.transform( p );
        const std::optional<double> h = dem.heightAt( q.x(), q.y() );
        return h ? p.z() - *h : std::numeric_limits<double>::quiet_NaN();
      };

      // Chord length: the deviation of the curve from a chord grows with its
      // square; start at 256 cells and halve until the midpoint is within
      // the tolerance (in grid units) of the curve.
      const std::array<double, 6> &gt = dem.geoTransform();
      const Eigen::Vector3d startInDem = blockToDem.transform( ray.origin );
      if ( !startInDem.allFinite() )
      {
        result.message = "the ray's start cannot be transformed into the DEM's CRS";
        return result;
      }
      const Eigen::Vector2d perUnit = dem.metresPerUnit( startInDem.x(), startInDem.y() );
      const double cellM = std::min( std::hypot( gt[1], gt[4] ) * perUnit.x(), std::hypot( gt[2], gt[5] ) * perUnit.y() );
      const double toleranceCells = 5e-5 / cellM;
      double chordM = 256.0 * cellM;
      Eigen::Vector2d a = gridAt( 0.0 ), firstEnd = gridAt( chordM );
      for ( int k = 0; k < 20; ++k )
      {
        const Eigen::Vector2d m = gridAt( 0.5 * chordM );
        if ( !m.allFinite() || !firstEnd.allFinite() || ( m - 0.5 * ( a + firstEnd ) ).norm() <= toleranceCells )
          break;
        chordM *= 0.5;
        firstEnd = m;
      }

      bool entered = false, left = false;
      double entry = 0.0;
      for ( double ta = 0.0; ta < options.maxRangeM; )
      {
        const double tb = std::min( ta + chordM, options.maxRangeM );
        const Eigen::Vector2d b = ta == 0.0 && tb == chordM ? firstEnd : gridAt( tb );
        if ( !a.allFinite() || !b.allFinite() )
        {
          if ( entered )
          {
            left = true;
            break;
          }
          a = b;
          ta = tb;
          continue;
        }
        const GridRay g = chord( a, b, ta, tb, ray.origin.z(), d.z() );
        double c0 = ta, c1 = tb;
        bool exits = false;
        if ( clipToDem( g, dem, c0, c1, exits ) )
        {
          if ( !entered )
          {
            entered = true;
            entry = c0;
          }
          const GridWalk walk = walkGrid( g, dem, c0, c1 );
          result.steps += walk.steps;
          if ( walk.hit && *walk.hit <= entry )
          {
            setBelowAtEntry( result, entry == 0.0 );
            return result;
          }
          if ( walk.hit )
          {
            // On the exact curve already, or refined there.
            const double t = std::abs( heightAbove( *walk.hit ) ) <= options.toleranceM ? *walk.hit : refineOnCurve( heightAbove, *walk.hit, entry, options.toleranceM );
            setHit( result, ray, d, t );
            return result;
          }
          if ( walk.hole )
          {
            setHole( result );
            return result;
          }
          if ( exits )
          {
            left = true;
            break;
          }
        }
        else if ( entered )
        {
          left = true;
          break;
        }
        a = b;
        ta = tb;
      }
      if ( left )
        result.message = "the ray leaves the DEM without meeting it";
      else if ( entered )
        result.message = "the ray does not meet the DEM within " + std::to_string( static_cast<long>( options.maxRangeM ) ) + " m";
      else
        result.message = "the ray does not pass over the DEM";
      return result;
    }
  } // namespace

  DemIntersection intersectRayWithDem( const Ray &ray, const Dem &dem, const CrsTransform &blockToDem, const DemIntersectionOptions &options )
  {
    const Eigen::Vector3d d = ray.direction.normalized();
    if ( blockToDem.isIdentity() )
      return intersectInGrid( ray, d, dem, options );
    return intersectAlongChords( ray, d, dem, blockToDem, options );
  }

} // namespace geostation
