/***************************************************************************
  demintersection.cpp - the first intersection of a ray with a DEM
 ***************************************************************************/
#include "dem/demintersection.h"

#include <sstream>

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <tuple>

namespace geostation
{

  namespace
  {
    constexpr double kInf = std::numeric_limits<double>::infinity();

    //! The ray in the DEM's cell-centre grid: (u, v) = pixel - 0.5, so vertex (i, j) sits at (i, j); z in height units.
    struct GridRay
    {
      double u0, v0, z0, du, dv, dz;
      double invDu, invDv, invDz; //!< 1 / du etc., infinite for 0
      // For stepping from cell to cell (set by prepare()): the range where
      // the ray reaches u = k is k * stepU + offsetU (+infinity if it never
      // does), and likewise for v.
      double stepU, offsetU, stepV, offsetV;
      int sx, sy; //!< the directions of travel in u and v (+1 or -1)

      double u( double t ) const { return u0 + t * du; }
      double v( double t ) const { return v0 + t * dv; }
      double z( double t ) const { return z0 + t * dz; }

      //! Sets the reciprocals and stepping terms from u0 ... dz.
      void prepare()
      {
        invDu = 1.0 / du;
        invDv = 1.0 / dv;
        invDz = 1.0 / dz;
        stepU = du != 0.0 ? invDu : 0.0;
        offsetU = du != 0.0 ? -u0 * invDu : kInf;
        stepV = dv != 0.0 ? invDv : 0.0;
        offsetV = dv != 0.0 ? -v0 * invDv : kInf;
        sx = du > 0.0 ? 1 : -1;
        sy = dv > 0.0 ? 1 : -1;
      }
    };

    /**
     * Visits the cells of side `size` (grid units, `invSize` its inverse)
     * that the ray crosses over [t0, t1] (over the DEM), indices kept within
     * [ixLo, ixHi] x [iyLo, iyHi] (>= 0); consecutive visits share their end
     * and start, so no part of the ray is skipped. visit(ix, iy, ta, tb)
     * returns true to stop; walkCells() then returns true.
     */
    template <class Visit>
    bool walkCells( const GridRay &ray, int size, double invSize, int ixLo, int ixHi, int iyLo, int iyHi, double t0, double t1, Visit &&visit )
    {
      // Positions are over the DEM (>= 0 but for rounding): truncation is floor(), or 0 for a rounding below.
      int ix = std::clamp( static_cast<int>( ray.u( t0 ) * invSize ), ixLo, ixHi ), iy = std::clamp( static_cast<int>( ray.v( t0 ) * invSize ), iyLo, iyHi );
      // Starting on a boundary while moving back: the first visit is empty, then the cell behind.
      const double deltaU = size * std::abs( ray.stepU ), deltaV = size * std::abs( ray.stepV );
      double nextU = ( ix + ( ray.sx > 0 ) ) * static_cast<double>( size ) * ray.stepU + ray.offsetU;
      double nextV = ( iy + ( ray.sy > 0 ) ) * static_cast<double>( size ) * ray.stepV + ray.offsetV;
      for ( double ta = t0;; )
      {
        const double tb = std::min( { nextU, nextV, t1 } );
        if ( tb >= ta && visit( ix, iy, ta, tb ) )
          return true;
        if ( tb >= t1 )
          return false;
        ta = std::max( ta, tb );
        if ( nextU < nextV )
        {
          ix += ray.sx;
          nextU += deltaU;
          if ( ix < ixLo || ix > ixHi )
            return false;
        }
        else
        {
          iy += ray.sy;
          nextV += deltaV;
          if ( iy < iyLo || iy > iyHi )
            return false;
        }
      }
    }

    /**
     * The first crossing of the ray with the bilinear patch of cell (i, j),
     * corners h00 (i, j), h10 (i + 1, j), h01 (i, j + 1), h11, over
     * [ta, tb]. Along the ray the height above the patch is a quadratic in t,
     * so the crossing is a root of it.
     */
    std::optional<double> crossingInCell( const GridRay &ray, int i, int j, double h00, double h10, double h01, double h11, double ta, double tb )
    {
      const double a0 = ray.u( ta ) - i, b0 = ray.v( ta ) - j;
      const double ga = h10 - h00, gb = h01 - h00, e = h00 - h10 - h01 + h11;
      // f(s) = c0 + c1 s + c2 s^2: height above the patch at t = ta + s
      const double c0 = ray.z( ta ) - ( h00 + ga * a0 + gb * b0 + e * a0 * b0 );
      const double c1 = ray.dz - ( ga * ray.du + gb * ray.dv + e * ( a0 * ray.dv + b0 * ray.du ) );
      const double c2 = -e * ray.du * ray.dv;
      const auto f = [&]( double s ) { return c0 + s * ( c1 + s * c2 ); };
      if ( c0 <= 0.0 )
        return ta;
      double hi = tb - ta;
      if ( f( hi ) > 0.0 )
      {
        // Above at both ends: only a parabola opening upwards can dip below in between.
        if ( c2 <= 0.0 )
          return std::nullopt;
        const double vertex = -c1 / ( 2.0 * c2 );
        if ( !( vertex > 0.0 && vertex < hi ) || f( vertex ) > 0.0 )
          return std::nullopt;
        hi = vertex;
      }
      // One sign change in (0, hi]: the root of the quadratic there, the
      // numerically stable way; bisection if rounding puts it outside.
      double root = -1.0;
      const double scale = std::abs( c1 ) + std::abs( c2 ) * hi;
      if ( std::abs( c2 ) * hi <= 1e-12 * scale )
        root = -c0 / c1;
      else
      {
        const double discriminant = c1 * c1 - 4.0 * c2 * c0;
        if ( discriminant >= 0.0 )
        {
          const double q = -0.5 * ( c1 + std::copysign( std::sqrt( discriminant ), c1 ) );
          const double r1 = q / c2, r2 = q != 0.0 ? c0 / q : -1.0;
          const double slack = 1e-9 * ( 1.0 + hi );
          if ( r1 >= -slack && r1 <= hi + slack && ( !( r2 >= -slack && r2 <= hi + slack ) || r1 <= r2 ) )
            root = r1;
          else if ( r2 >= -slack && r2 <= hi + slack )
            root = r2;
        }
      }
      if ( !( root >= 0.0 && root <= hi ) )
      {
        double lo = 0.0, up = hi;
        for ( int k = 0; k < 60 && up - lo > 1e-9; ++k )
          ( f( 0.5 * ( lo + up ) ) > 0.0 ? lo : up ) = 0.5 * ( lo + up );
        root = 0.5 * ( lo + up );
      }
      return ta + std::clamp( root, 0.0, hi );
    }

    //! The straight grid ray through two grid points (u, v) at ranges ta < tb of the block ray, z from the block ray.
    GridRay chord( const Eigen::Vector2d &a, const Eigen::Vector2d &b, double ta, double tb, double z0, double dz )
    {
      GridRay g;
      g.du = ( b.x() - a.x() ) / ( tb - ta );
      g.dv = ( b.y() - a.y() ) / ( tb - ta );
      g.u0 = a.x() - ta * g.du;
      g.v0 = a.y() - ta * g.dv;
      g.z0 = z0;
      g.dz = dz;
      g.prepare();
      return g;
    }

    /**
     * Shortens [t0, t1] to where the grid ray is over the cell-centre area
     * [0, W - 1] x [0, H - 1]; false if it is nowhere over it. `exits` tells
     * whether t1 was shortened.
     */
    bool clipToDem( const GridRay &g, const Dem &dem, double &t0, double &t1, bool &exits )
    {
      exits = false;
      // One axis: position p0 + t dp within [0, extent].
      const auto clipAxis = [&]( double p0, double dp, double invDp, double extent )
      {
        if ( dp == 0.0 )
          return p0 >= 0.0 && p0 <= extent;
        const double ta = ( ( dp > 0.0 ? 0.0 : extent ) - p0 ) * invDp, tb = ( ( dp > 0.0 ? extent : 0.0 ) - p0 ) * invDp;
        t0 = std::max( t0, ta );
        if ( tb < t1 )
        {
          t1 = tb;
          exits = true;
        }
        return true;
      };
      return clipAxis( g.u0, g.du, g.invDu, dem.width() - 1.0 ) && clipAxis( g.v0, g.dv, g.invDv, dem.height() - 1.0 ) && t0 <= t1;
    }

    struct GridWalk
    {
      std::optional<double> hit; //!< range of the first crossing
      bool hole = false;
      int steps = 0;
    };

    /**
     * Walks tiles, blocks and cells along the straight grid ray over [t0, t1]
     * (over the DEM): tiles and blocks whose highest corner the ray stays
     * above are passed over, the remaining cells solved exactly.
     */
    GridWalk walkGrid( const GridRay &g, const Dem &dem, double t0, double t1 )
    {
      GridWalk walk;
      const int T = dem.tileSize(), B = Dem::kBlockSize;
      const double invT = 1.0 / T;
      const int lastCellX = dem.width() - 2, lastCellY = dem.height() - 2;
      // Shortens [ta, tb] to where the ray is not above height `top`; false if nowhere.
      const auto clipBelow = [&g]( double top, double &ta, double &tb )
      {
        if ( g.dz < 0.0 )
          ta = std::max( ta, ( top - g.z0 ) * g.invDz );
        else if ( g.dz > 0.0 )
          tb = std::min( tb, ( top - g.z0 ) * g.invDz );
        else if ( g.z0 > top )
          return false;
        return ta <= tb;
      };
      walkCells( g, T, invT, 0, lastCellX / T, 0, lastCellY / T, t0, t1, [&]( int tx, int ty, double ta, double tb )
      {
        ++walk.steps;
        Dem::TileView view;
        if ( !dem.tileView( tx, ty, view ) || !clipBelow( view.maxHeight, ta, tb ) )
          return false;
        const Dem::TileView *tile = &view;
        const int bx0 = tx * T / B, by0 = ty * T / B;
        return walkCells( g, B, 1.0 / B, bx0, std::min( bx0 + tile->blocksPerSide - 1, lastCellX / B ), by0, std::min( by0 + tile->blocksPerSide - 1, lastCellY / B ), ta, tb,
                          [&]( int bx, int by, double ba, double bb )
        {
          ++walk.steps;
          if ( !clipBelow( tile->blockMax[( by - by0 ) * tile->blocksPerSide + ( bx - bx0 )], ba, bb ) )
            return false;
          return walkCells( g, 1, 1.0, bx * B, std::min( bx * B + B - 1, lastCellX ), by * B, std::min( by * B + B - 1, lastCellY ), ba, bb,
                            [&]( int i, int j, double ca, double cb )
          {
            ++walk.steps;
            const float *corner = tile->vertices + static_cast<size_t>( j - ty * T ) * tile->stride + ( i - tx * T );
            const double h00 = corner[0], h10 = corner[1], h01 = corner[tile->stride], h11 = corner[tile->stride + 1];
            if ( std::isnan( h00 + h10 + h01 + h11 ) )
            {
              walk.hole = true; // under the block's bound: the hole may reach the ray
              return true;
            }
            if ( !clipBelow( std::max( { h00, h10, h01, h11 } ), ca, cb ) )
              return false;
            walk.hit = crossingInCell( g, i, j, h00, h10, h01, h11, ca, cb );
            return walk.hit.has_value();
          } );
        } );
      } );
      return walk;
    }

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

    std::string outOfRange( const DemIntersectionOptions &options )
    {
      return "the ray does not meet the DEM within " + std::to_string( static_cast<long>( options.maxRangeM ) ) + " m";
    }

    //! The fill limit in cells and in the DEM's ground units, for the message.
    void setHole( DemIntersection &result, const Dem &dem )
    {
      result.status = DemIntersection::Status::Hole;
      const bool bridged = dem.bridgeHolesUpToCells() > 2 * dem.holeFillHalo();
      const int cells = bridged ? dem.bridgeHolesUpToCells() : 2 * dem.holeFillHalo();
      const double across = cells * std::abs( dem.geoTransform()[1] );
      std::ostringstream limit;
      limit.precision( dem.isGeographic() ? 3 : 0 );
      limit << std::fixed << ( dem.isGeographic() ? across * 3600.0 : across ) << ( dem.isGeographic() ? " arc seconds" : " m" );
      result.message = "the ray meets a nodata hole in the DEM too large to fill (holes up to about " + std::to_string( cells ) + " cells, " + limit.str() +
                       ( bridged ? ", across are bridged)" : ", across are filled from their neighbours; larger ones can be bridged)" );
    }

    Eigen::Vector2d gridPoint( const Dem &dem, const Eigen::Vector3d &inDem )
    {
      const std::array<double, 6> &inv = dem.inverseGeoTransform();
      return { inv[0] + inv[1] * inDem.x() + inv[2] * inDem.y() - 0.5, inv[3] + inv[4] * inDem.x() + inv[5] * inDem.y() - 0.5 };
    }

    //! A DEM in the block's own CRS: the ray is straight in its grid.
    DemIntersection intersectInGrid( const Ray &ray, const Eigen::Vector3d &d, const Dem &dem, const DemIntersectionOptions &options )
    {
      DemIntersection result;
      const std::array<double, 6> &inv = dem.inverseGeoTransform();
      const Eigen::Vector2d start = gridPoint( dem, ray.origin );
      GridRay g;
      g.u0 = start.x();
      g.v0 = start.y();
      g.z0 = ray.origin.z();
      g.du = inv[1] * d.x() + inv[2] * d.y();
      g.dv = inv[4] * d.x() + inv[5] * d.y();
      g.dz = d.z();
      g.prepare();
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
        setHole( result, dem );
      else
        result.message = exits ? "the ray leaves the DEM without meeting it" : outOfRange( options );
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
            setHole( result, dem );
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
        result.message = outOfRange( options );
      else
        result.message = "the ray does not pass over the DEM";
      return result;
    }
  } // namespace

  DemIntersection intersectRayWithDem( const Ray &ray, const Dem &dem, const CrsTransform &blockToDem, const DemIntersectionOptions &options )
  {
    const Eigen::Vector3d d = ray.direction * ( 1.0 / ray.direction.norm() );
    if ( blockToDem.isIdentity() )
      return intersectInGrid( ray, d, dem, options );
    return intersectAlongChords( ray, d, dem, blockToDem, options );
  }

  std::string demIntersectionStatusName( DemIntersection::Status status )
  {
    switch ( status )
    {
      case DemIntersection::Status::Hit:
        return "ok";
      case DemIntersection::Status::Miss:
        return "misses_dem";
      case DemIntersection::Status::BelowSurface:
        return "below_dem";
      case DemIntersection::Status::Hole:
        return "dem_hole";
    }
    return "misses_dem";
  }

  GroundOfPixel demGroundOfPixel( const Dem &dem, const CrsTransform &blockToDem, const DemIntersectionOptions &options )
  {
    return [&dem, &blockToDem, options]( const OrientedImage &image, const Eigen::Vector2d &pixel ) -> std::optional<Eigen::Vector3d>
    {
      const std::optional<Ray> ray = image.worldRayFromPixel( pixel );
      if ( !ray )
        return std::nullopt;
      const DemIntersection hit = intersectRayWithDem( *ray, dem, blockToDem, options );
      return hit.hit() ? std::optional<Eigen::Vector3d>( hit.point ) : std::nullopt;
    };
  }

  std::function<std::optional<double>( double x, double y )> demHeightAt( const Dem &dem, const CrsTransform &blockToDem )
  {
    return [&dem, &blockToDem]( double x, double y )
    {
      const Eigen::Vector3d inDem = blockToDem.transform( Eigen::Vector3d( x, y, 0.0 ) );
      return dem.heightAt( inDem.x(), inDem.y() );
    };
  }

} // namespace geostation
