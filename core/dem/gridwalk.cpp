/***************************************************************************
  gridwalk.cpp - walking a straight ray through a DEM's grid
 ***************************************************************************/
#include "dem/gridwalk.h"

#include <algorithm>
#include <cmath>
#include <tuple>

namespace geostation::gridwalk
{

  namespace
  {
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
  } // namespace

  // Along the ray the height above the patch is a quadratic in t: the crossing is a root of it.
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

  GridRay chord( const Eigen::Vector2d &a, const Eigen::Vector2d &b, double ta, double tb, double z0, double dz )
  {
    GridRay g;
    g.du = ( b.x() - a.x() ) / ( tb - ta );
    g.dv = ( b.y() - a.y() ) / ( tb - ta );
    g.u0 = a.x() - ta * g.du;
    g.v0 = a.y() - ta * g.dv;
    g.z0 = z0;
    g.dz = dz;
    g.invDu = 1.0 / g.du;
    g.invDv = 1.0 / g.dv;
    g.invDz = 1.0 / g.dz;
    return g;
  }

  bool clipToDem( const GridRay &g, const Dem &dem, double &t0, double &t1, bool &exits )
  {
    exits = false;
    for ( const auto &[p, dp, invDp, extent] : { std::tuple<double, double, double, double> { g.u0, g.du, g.invDu, dem.width() - 1.0 }, { g.v0, g.dv, g.invDv, dem.height() - 1.0 } } )
    {
      if ( dp == 0.0 )
      {
        if ( !( p >= 0.0 && p <= extent ) )
          return false;
        continue;
      }
      const double ta = ( ( dp > 0.0 ? 0.0 : extent ) - p ) * invDp, tb = ( ( dp > 0.0 ? extent : 0.0 ) - p ) * invDp;
      t0 = std::max( t0, ta );
      if ( tb < t1 )
      {
        t1 = tb;
        exits = true;
      }
    }
    return t0 <= t1;
  }


  GridWalk walkGrid( const GridRay &g, const Dem &dem, double t0, double t1 )
  {
    GridWalk walk;
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
    walkCells( g, T, 0, lastCellX / T, 0, lastCellY / T, t0, t1, [&]( int tx, int ty, double ta, double tb )
    {
      ++walk.steps;
      Dem::TileView view;
      if ( !dem.tileView( tx, ty, view ) || !clipBelow( view.maxHeight, ta, tb ) )
        return false;
      const Dem::TileView *tile = &view;
      const int bx0 = tx * T / B, by0 = ty * T / B;
      return walkCells( g, B, bx0, std::min( bx0 + tile->blocksPerSide - 1, lastCellX / B ), by0, std::min( by0 + tile->blocksPerSide - 1, lastCellY / B ), ta, tb,
                        [&]( int bx, int by, double ba, double bb )
      {
        ++walk.steps;
        if ( !clipBelow( tile->blockMax[( by - by0 ) * tile->blocksPerSide + ( bx - bx0 )], ba, bb ) )
          return false;
        return walkCells( g, 1, bx * B, std::min( bx * B + B - 1, lastCellX ), by * B, std::min( by * B + B - 1, lastCellY ), ba, bb,
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

  Eigen::Vector2d gridPoint( const Dem &dem, const Eigen::Vector3d &inDem )
  {
    const std::array<double, 6> &inv = dem.inverseGeoTransform();
    return { inv[0] + inv[1] * inDem.x() + inv[2] * inDem.y() - 0.5, inv[3] + inv[4] * inDem.x() + inv[5] * inDem.y() - 0.5 };
  }

} // namespace geostation::gridwalk
