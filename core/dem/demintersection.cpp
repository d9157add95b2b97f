/***************************************************************************
  demintersection.cpp - the first intersection of a ray with a DEM
 ***************************************************************************/
#include "dem/demintersection.h"

#include <cmath>
#include <limits>

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
      double u( double t ) const { return u0 + t * du; }
      double v( double t ) const { return v0 + t * dv; }
      double z( double t ) const { return z0 + t * dz; }
    };

    /**
     * Visits the cells of side `size` (grid units) that the ray crosses over
     * [t0, t1], indices kept within [ixLo, ixHi] x [iyLo, iyHi]; consecutive
     * visits share their end and start, so no part of the ray is skipped.
     * visit(ix, iy, ta, tb) returns true to stop; walk() then returns true.
     */
    template <class Visit>
    bool walkCells( const GridRay &ray, int size, int ixLo, int ixHi, int iyLo, int iyHi, double t0, double t1, Visit &&visit )
    {
      const double invSize = 1.0 / size;
      const auto start = [invSize]( double p, double d, int lo, int hi )
      {
        // floor() without a library call (t0 lies over the DEM: no overflow)
        const double cellsIn = std::clamp( p * invSize, lo - 1.0, hi + 1.0 );
        int i = static_cast<int>( cellsIn );
        if ( i > cellsIn )
          --i;
        if ( d < 0.0 && cellsIn == i )
          --i; // on a boundary, moving back: the cell behind it
        return std::clamp( i, lo, hi );
      };
      int ix = start( ray.u( t0 ), ray.du, ixLo, ixHi ), iy = start( ray.v( t0 ), ray.dv, iyLo, iyHi );
      const int sx = ray.du > 0.0 ? 1 : -1, sy = ray.dv > 0.0 ? 1 : -1;
      const double deltaU = ray.du != 0.0 ? size * std::abs( ray.invDu ) : kInf;
      const double deltaV = ray.dv != 0.0 ? size * std::abs( ray.invDv ) : kInf;
      double nextU = ray.du != 0.0 ? ( ( ix + ( sx > 0 ? 1 : 0 ) ) * static_cast<double>( size ) - ray.u0 ) * ray.invDu : kInf;
      double nextV = ray.dv != 0.0 ? ( ( iy + ( sy > 0 ? 1 : 0 ) ) * static_cast<double>( size ) - ray.v0 ) * ray.invDv : kInf;
      for ( double ta = t0;; )
      {
        const double tb = std::min( { nextU, nextV, t1 } );
        if ( tb >= ta && visit( ix, iy, ta, std::max( ta, tb ) ) )
          return true;
        if ( tb >= t1 )
          return false;
        if ( nextU < nextV )
        {
          ix += sx;
          nextU += deltaU;
          if ( ix < ixLo || ix > ixHi )
            return false;
        }
        else
        {
          iy += sy;
          nextV += deltaV;
          if ( iy < iyLo || iy > iyHi )
            return false;
        }
        ta = std::max( ta, tb );
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

    /**
     * Exact traversal for a DEM in the block's own CRS: the ray is straight
     * in the grid, tiles and blocks whose highest corner lies below the ray
     * are passed over, and each cell the ray may meet is solved exactly.
     */
    DemIntersection intersectInGrid( const Ray &ray, const Eigen::Vector3d &d, const Dem &dem, const DemIntersectionOptions &options )
    {
      DemIntersection result;
      const std::array<double, 6> &inv = dem.inverseGeoTransform();
      GridRay g;
      g.u0 = inv[0] + inv[1] * ray.origin.x() + inv[2] * ray.origin.y() - 0.5;
      g.v0 = inv[3] + inv[4] * ray.origin.x() + inv[5] * ray.origin.y() - 0.5;
      g.z0 = ray.origin.z();
      g.du = inv[1] * d.x() + inv[2] * d.y();
      g.dv = inv[4] * d.x() + inv[5] * d.y();
      g.dz = d.z();
      g.invDu = 1.0 / g.du;
      g.invDv = 1.0 / g.dv;
      g.invDz = 1.0 / g.dz;

      // The part of the ray over the cell-centre area [0, W - 1] x [0, H - 1].
      double t0 = 0.0, t1 = options.maxRangeM;
      bool rangeLimited = true;
      for ( const auto &[p, dp, invDp, extent] : { std::tuple<double, double, double, double> { g.u0, g.du, g.invDu, dem.width() - 1.0 }, { g.v0, g.dv, g.invDv, dem.height() - 1.0 } } )
      {
        if ( dp == 0.0 )
        {
          if ( p < 0.0 || p > extent )
            t1 = -1.0;
          continue;
        }
        const double ta = ( ( dp > 0.0 ? 0.0 : extent ) - p ) * invDp, tb = ( ( dp > 0.0 ? extent : 0.0 ) - p ) * invDp;
        t0 = std::max( t0, ta );
        if ( tb < t1 )
        {
          t1 = tb;
          rangeLimited = false;
        }
      }
      if ( t1 < t0 )
      {
        result.message = "the ray does not pass over the DEM";
        return result;
      }

      const int T = dem.tileSize(), B = Dem::kBlockSize;
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
      std::optional<double> hitT;
      bool hole = false;
      walkCells( g, T, 0, lastCellX / T, 0, lastCellY / T, t0, t1, [&]( int tx, int ty, double ta, double tb )
      {
        ++result.steps;
        Dem::TileView view;
        if ( !dem.tileView( tx, ty, view ) || !clipBelow( view.maxHeight, ta, tb ) )
          return false;
        const Dem::TileView *tile = &view;
        const int bx0 = tx * T / B, by0 = ty * T / B;
        return walkCells( g, B, bx0, std::min( bx0 + tile->blocksPerSide - 1, lastCellX / B ), by0, std::min( by0 + tile->blocksPerSide - 1, lastCellY / B ), ta, tb,
                          [&]( int bx, int by, double ba, double bb )
        {
          ++result.steps;
          if ( !clipBelow( tile->blockMax[( by - by0 ) * tile->blocksPerSide + ( bx - bx0 )], ba, bb ) )
            return false;
          return walkCells( g, 1, bx * B, std::min( bx * B + B - 1, lastCellX ), by * B, std::min( by * B + B - 1, lastCellY ), ba, bb,
                            [&]( int i, int j, double ca, double cb )
          {
            ++result.steps;
            const float *corner = tile->vertices + static_cast<size_t>( j - ty * T ) * tile->stride + ( i - tx * T );
            const double h00 = corner[0], h10 = corner[1], h01 = corner[tile->stride], h11 = corner[tile->stride + 1];
            if ( std::isnan( h00 + h10 + h01 + h11 ) )
            {
              hole = true; // under the block's bound: the hole may reach the ray
              return true;
            }
            if ( !clipBelow( std::max( { h00, h10, h01, h11 } ), ca, cb ) )
              return false;
            hitT = crossingInCell( g, i, j, h00, h10, h01, h11, ca, cb );
            return hitT.has_value();
          } );
        } );
      } );
      if ( hitT && *hitT <= t0 )
      {
        // Below (or on) the surface where the ray comes over the DEM.
        if ( t0 == 0.0 )
        {
          result.status = DemIntersection::Status::BelowSurface;
          result.message = "the ray starts below the terrain (is the camera height in the DEM's vertical datum?)";
        }
        else
          result.message = "the ray enters the DEM's area below its surface";
        return result;
      }
      if ( hitT )
      {
        result.status = DemIntersection::Status::Hit;
        result.rangeM = *hitT;
        result.point = ray.origin + *hitT * d;
        return result;
      }
      if ( hole )
      {
        result.status = DemIntersection::Status::Hole;
        result.message = "the ray meets a hole in the DEM too large to fill";
        return result;
      }
      result.message = rangeLimited ? "the ray does not meet the DEM within " + std::to_string( static_cast<long>( options.maxRangeM ) ) + " m"
                       : "the ray leaves the DEM without meeting it";
      return result;
    }
  } // namespace

  DemIntersection intersectRayWithDem( const Ray &ray, const Dem &dem, const CrsTransform &blockToDem, const DemIntersectionOptions &options )
  {
    if ( blockToDem.isIdentity() )
      return intersectInGrid( ray, ray.direction.normalized(), dem, options );

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
