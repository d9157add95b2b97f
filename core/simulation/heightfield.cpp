/***************************************************************************
  heightfield.cpp - the simulator's terrain grid and exact ray casting
 ***************************************************************************/
#include "simulation/heightfield.h"
#include "io/rasterfile.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <stdexcept>

#include <gdal.h>
#include <ogr_srs_api.h>

namespace geostation
{
  namespace
  {
    constexpr double kInf = std::numeric_limits<double>::infinity();

    /**
     * Walks the cells of size `cellSize` (grid units) that the ray
     * g(t) = g0 + gd t crosses for t in [ta, tb], on a grid of nx x ny cells,
     * calling visit(ci, cj, t0, t1) until it returns true (then returns true).
     */
    template <typename Visit>
    bool walkCells( const Eigen::Vector2d &g0, const Eigen::Vector2d &gd, double ta, double tb, double cellSize, int nx, int ny, Visit &&visit )
    {
      const Eigen::Vector2d p = g0 + gd * ta;
      int ci = std::clamp( static_cast<int>( std::floor( p.x() / cellSize ) ), 0, nx - 1 );
      int cj = std::clamp( static_cast<int>( std::floor( p.y() / cellSize ) ), 0, ny - 1 );
      const int stepX = gd.x() > 0 ? 1 : -1;
      const int stepY = gd.y() > 0 ? 1 : -1;
      double tMaxX = kInf, tMaxY = kInf, tDeltaX = kInf, tDeltaY = kInf;
      if ( gd.x() != 0.0 )
      {
        tMaxX = ta + ( ( ci + ( stepX > 0 ? 1 : 0 ) ) * cellSize - p.x() ) / gd.x();
        tDeltaX = cellSize / std::abs( gd.x() );
      }
      if ( gd.y() != 0.0 )
      {
        tMaxY = ta + ( ( cj + ( stepY > 0 ? 1 : 0 ) ) * cellSize - p.y() ) / gd.y();
        tDeltaY = cellSize / std::abs( gd.y() );
      }
      double tCur = ta;
      while ( true )
      {
        const double tNext = std::min( { tMaxX, tMaxY, tb } );
        if ( visit( ci, cj, tCur, std::max( tCur, tNext ) ) )
          return true;
        if ( tNext >= tb )
          return false;
        if ( tMaxX < tMaxY )
        {
          ci += stepX;
          tMaxX += tDeltaX;
        }
        else
        {
          cj += stepY;
          tMaxY += tDeltaY;
        }
        tCur = tNext;
        if ( ci < 0 || ci >= nx || cj < 0 || cj >= ny )
          return false;
      }
    }
  }

  HeightField::HeightField( double originX, double originY, double spacing, int width, int height,
                            const std::function<double( double, double )> &heightAt )
    : mOriginX( originX ), mOriginY( originY ), mSpacing( spacing ), mWidth( width ), mHeight( height )
  {
    if ( width < 2 || height < 2 || !( spacing > 0.0 ) )
      throw std::invalid_argument( "a height field needs at least 2 x 2 nodes and a positive spacing" );
    mNodes.resize( static_cast<size_t>( width ) * height );
    mMinHeight = kInf;
    mMaxHeight = -kInf;
    for ( int j = 0; j < height; ++j )
      for ( int i = 0; i < width; ++i )
      {
        const float h = static_cast<float>( heightAt( originX + i * spacing, originY - j * spacing ) );
        if ( !std::isfinite( h ) )
          throw std::invalid_argument( "a height field node has no finite height" );
        mNodes[static_cast<size_t>( j ) * width + i] = h;
        mMinHeight = std::min<double>( mMinHeight, h );
        mMaxHeight = std::max<double>( mMaxHeight, h );
      }
    mBlocksX = ( width - 1 + kBlock - 1 ) / kBlock;
    mBlocksY = ( height - 1 + kBlock - 1 ) / kBlock;
    mBlockMax.assign( static_cast<size_t>( mBlocksX ) * mBlocksY, -std::numeric_limits<float>::infinity() );
    for ( int bj = 0; bj < mBlocksY; ++bj )
      for ( int bi = 0; bi < mBlocksX; ++bi )
      {
        float m = -std::numeric_limits<float>::infinity();
        for ( int j = bj * kBlock; j <= std::min( ( bj + 1 ) * kBlock, height - 1 ); ++j )
          for ( int i = bi * kBlock; i <= std::min( ( bi + 1 ) * kBlock, width - 1 ); ++i )
            m = std::max( m, mNodes[static_cast<size_t>( j ) * width + i] );
        mBlockMax[static_cast<size_t>( bj ) * mBlocksX + bi] = m;
      }
    mSupersX = ( mBlocksX + kSuper - 1 ) / kSuper;
    mSupersY = ( mBlocksY + kSuper - 1 ) / kSuper;
    mSuperMax.assign( static_cast<size_t>( mSupersX ) * mSupersY, -std::numeric_limits<float>::infinity() );
    for ( int bj = 0; bj < mBlocksY; ++bj )
      for ( int bi = 0; bi < mBlocksX; ++bi )
      {
        float &m = mSuperMax[static_cast<size_t>( bj / kSuper ) * mSupersX + bi / kSuper];
        m = std::max( m, mBlockMax[static_cast<size_t>( bj ) * mBlocksX + bi] );
      }
  }

  bool HeightField::covers( double x, double y ) const
  {
    const double gx = ( x - mOriginX ) / mSpacing, gy = ( mOriginY - y ) / mSpacing;
    return gx >= 0.0 && gy >= 0.0 && gx <= mWidth - 1 && gy <= mHeight - 1;
  }

  std::optional<double> HeightField::heightAt( double x, double y ) const
  {
    if ( !covers( x, y ) )
      return std::nullopt;
    const double gx = ( x - mOriginX ) / mSpacing, gy = ( mOriginY - y ) / mSpacing;
    const int i = std::min( static_cast<int>( gx ), mWidth - 2 ), j = std::min( static_cast<int>( gy ), mHeight - 2 );
    const double u = gx - i, v = gy - j;
    return ( 1 - u ) * ( 1 - v ) * nodeHeight( i, j ) + u * ( 1 - v ) * nodeHeight( i + 1, j ) + ( 1 - u ) * v * nodeHeight( i, j + 1 ) + u * v * nodeHeight( i + 1, j + 1 );
  }

  Eigen::Vector3d HeightField::normalAt( double x, double y ) const
  {
    const double gx = std::clamp( ( x - mOriginX ) / mSpacing, 0.0, mWidth - 1.0 );
    const double gy = std::clamp( ( mOriginY - y ) / mSpacing, 0.0, mHeight - 1.0 );
    const int i = std::min( static_cast<int>( gx ), mWidth - 2 ), j = std::min( static_cast<int>( gy ), mHeight - 2 );
    const double u = gx - i, v = gy - j;
    const double h00 = nodeHeight( i, j ), h10 = nodeHeight( i + 1, j ), h01 = nodeHeight( i, j + 1 ), h11 = nodeHeight( i + 1, j + 1 );
    const double d = h00 - h10 - h01 + h11;
    const double dhdu = ( h10 - h00 ) + d * v, dhdv = ( h01 - h00 ) + d * u;
    return Eigen::Vector3d( -dhdu / mSpacing, dhdv / mSpacing, 1.0 ).normalized();
  }

  bool HeightField::intersectPatch( int i, int j, const Eigen::Vector3d &origin, const Eigen::Vector3d &direction,
                                    double t0, double t1, double &tHit ) const
  {
    const double h00 = nodeHeight( i, j ), h10 = nodeHeight( i + 1, j ), h01 = nodeHeight( i, j + 1 ), h11 = nodeHeight( i + 1, j + 1 );
    const double z0 = origin.z() + direction.z() * t0, z1 = origin.z() + direction.z() * t1;
    if ( std::min( z0, z1 ) > std::max( { h00, h10, h01, h11 } ) )
      return false;
    const double u0 = ( origin.x() + direction.x() * t0 - mOriginX ) / mSpacing - i;
    const double v0 = ( mOriginY - ( origin.y() + direction.y() * t0 ) ) / mSpacing - j;
    const double du = direction.x() / mSpacing, dv = -direction.y() / mSpacing;
    const double a = h00, b = h10 - h00, c = h01 - h00, d = h00 - h10 - h01 + h11;
    const double A = -d * du * dv;
    const double B = direction.z() - b * du - c * dv - d * ( u0 * dv + v0 * du );
    const double C = z0 - ( a + b * u0 + c * v0 + d * u0 * v0 );
    const double length = t1 - t0;
    if ( C <= 0.0 )
    {
      tHit = t0;
      return true;
    }
    double tau = kInf;
    if ( std::abs( A ) < 1e-14 )
    {
      if ( B < 0.0 )
        tau = -C / B;
    }
    else
    {
      const double disc = B * B - 4.0 * A * C;
      if ( disc >= 0.0 )
      {
        const double sq = std::sqrt( disc );
        const double q = -0.5 * ( B + ( B >= 0.0 ? sq : -sq ) );
        double r1 = q / A, r2 = q != 0.0 ? C / q : kInf;
        if ( r1 > r2 )
          std::swap( r1, r2 );
        tau = r1 >= 0.0 ? r1 : ( r2 >= 0.0 ? r2 : kInf );
      }
    }
    if ( tau <= length * ( 1.0 + 1e-12 ) + 1e-12 )
    {
      tHit = t0 + std::min( tau, length );
      return true;
    }
    return false;
  }

  std::optional<TerrainHit> HeightField::intersect( const Eigen::Vector3d &origin, const Eigen::Vector3d &direction,
      double tMin, double tMax ) const
  {
    // Grid coordinates g = ((x - x0) / s, (y0 - y) / s); clip to the grid and the height range.
    const Eigen::Vector2d g0( ( origin.x() - mOriginX ) / mSpacing, ( mOriginY - origin.y() ) / mSpacing );
    const Eigen::Vector2d gd( direction.x() / mSpacing, -direction.y() / mSpacing );
    double ta = tMin, tb = tMax;
    const auto clip = [&]( double o, double d, double lo, double hi )
    {
      if ( d == 0.0 )
      {
        if ( o < lo || o > hi )
          tb = -kInf;
        return;
      }
      double t0 = ( lo - o ) / d, t1 = ( hi - o ) / d;
      if ( t0 > t1 )
        std::swap( t0, t1 );
      ta = std::max( ta, t0 );
      tb = std::min( tb, t1 );
    };
    clip( g0.x(), gd.x(), 0.0, mWidth - 1.0 );
    clip( g0.y(), gd.y(), 0.0, mHeight - 1.0 );
    clip( origin.z(), direction.z(), -kInf, mMaxHeight );
    if ( direction.z() == 0.0 && origin.z() > mMaxHeight )
      return std::nullopt;
    if ( !( ta <= tb ) )
      return std::nullopt;

    double tHit = kInf;
    const auto below = [&]( double t0, double t1, double top )
    {
      return std::min( origin.z() + direction.z() * t0, origin.z() + direction.z() * t1 ) <= top;
    };
    const bool hit = walkCells( g0, gd, ta, tb, kBlock * kSuper, mSupersX, mSupersY, [&]( int si, int sj, double st0, double st1 )
    {
      if ( !below( st0, st1, superMax( si, sj ) ) )
        return false;
      const Eigen::Vector2d superOrigin( si * kBlock * kSuper, sj * kBlock * kSuper );
      const int nbx = std::min( kSuper, mBlocksX - si * kSuper ), nby = std::min( kSuper, mBlocksY - sj * kSuper );
      return walkCells( g0 - superOrigin, gd, st0, st1, kBlock, nbx, nby, [&]( int ci, int cj, double bt0, double bt1 )
      {
        const int bi = si * kSuper + ci, bj = sj * kSuper + cj;
        if ( !below( bt0, bt1, blockMax( bi, bj ) ) )
          return false;
        const Eigen::Vector2d blockOrigin( bi * kBlock, bj * kBlock );
        const int nx = std::min( kBlock, mWidth - 1 - bi * kBlock ), ny = std::min( kBlock, mHeight - 1 - bj * kBlock );
        return walkCells( g0 - blockOrigin, gd, bt0, bt1, 1.0, nx, ny, [&]( int pi, int pj, double pt0, double pt1 )
        {
          return intersectPatch( bi * kBlock + pi, bj * kBlock + pj, origin, direction, pt0, pt1, tHit );
        } );
      } );
    } );
    if ( !hit )
      return std::nullopt;
    TerrainHit result;
    result.t = tHit;
    result.point = origin + direction * tHit;
    // the exact surface height at the hit, so truth and rendering agree to the float grid
    if ( const std::optional<double> h = heightAt( result.point.x(), result.point.y() ) )
      result.point.z() = *h;
    result.normal = normalAt( result.point.x(), result.point.y() );
    return result;
  }

  void HeightField::writeGeoTiff( const std::string &path, const std::string &crs ) const
  {
    registerGdalDrivers();
    GDALDriverH driver = GDALGetDriverByName( "GTiff" );
    const char *options[] = { "TILED=YES", "COMPRESS=DEFLATE", "PREDICTOR=3", nullptr };
    GDALDatasetH ds = GDALCreate( driver, path.c_str(), mWidth, mHeight, 1, GDT_Float32, const_cast<char **>( options ) );
    if ( !ds )
      throw std::runtime_error( "cannot create the terrain file " + path );
    std::array<double, 6> gt { mOriginX - 0.5 * mSpacing, mSpacing, 0.0, mOriginY + 0.5 * mSpacing, 0.0, -mSpacing };
    GDALSetGeoTransform( ds, gt.data() );
    OGRSpatialReferenceH srs = OSRNewSpatialReference( nullptr );
    OSRSetFromUserInput( srs, crs.c_str() );
    GDALSetSpatialRef( ds, srs );
    OSRDestroySpatialReference( srs );
    const CPLErr err = GDALRasterIO( GDALGetRasterBand( ds, 1 ), GF_Write, 0, 0, mWidth, mHeight, const_cast<float *>( mNodes.data() ),
                                     mWidth, mHeight, GDT_Float32, 0, 0 );
    GDALClose( ds );
    if ( err != CE_None )
      throw std::runtime_error( "cannot write the terrain file " + path );
  }

} // namespace geostation
