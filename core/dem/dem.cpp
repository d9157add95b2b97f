/***************************************************************************
  dem.cpp - a digital elevation model read through GDAL
 ***************************************************************************/
#include "dem/dem.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include <cpl_conv.h>
#include <cpl_error.h>
#include <gdal.h>
#include <ogr_srs_api.h>

namespace geostation
{

  namespace
  {
    constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  }

  Dem::Dem( const std::string &path, const DemOptions &options )
    : mOptions( options )
  {
    if ( options.tileSize < kBlockSize || options.tileSize % kBlockSize != 0 || options.holeFillHalo < 0 || options.cacheTiles < 9 )
      throw std::invalid_argument( "DEM options: tiles of a multiple of 8 cells, a non-negative halo and at least 9 cached tiles" );
    GDALAllRegister();
    CPLPushErrorHandler( CPLQuietErrorHandler );
    mDataset = GDALOpenEx( path.c_str(), GDAL_OF_RASTER | GDAL_OF_READONLY, nullptr, nullptr, nullptr );
    CPLPopErrorHandler();
    if ( !mDataset )
      throw std::runtime_error( "cannot open the DEM " + path );
    const auto fail = [this, &path]( const std::string & why )
    {
      GDALClose( mDataset );
      mDataset = nullptr;
      throw std::runtime_error( "the DEM " + path + " " + why );
    };
    if ( GDALGetGeoTransform( mDataset, mGeoTransform.data() ) != CE_None || !GDALInvGeoTransform( mGeoTransform.data(), mInverse.data() ) )
      fail( "has no usable georeferencing (geotransform)" );
    OGRSpatialReferenceH srs = GDALGetSpatialRef( mDataset );
    if ( !srs )
      fail( "has no CRS; assign one (e.g. with gdal_edit.py -a_srs) so it can be placed under the block" );
    char *wkt = nullptr;
    OSRExportToWkt( srs, &wkt );
    mCrsWkt = wkt ? wkt : "";
    CPLFree( wkt );
    mGeographic = OSRIsGeographic( srs );
    mWidth = GDALGetRasterXSize( mDataset );
    mHeight = GDALGetRasterYSize( mDataset );
    if ( mWidth < 2 || mHeight < 2 )
      fail( "needs at least 2 x 2 cells" );
    int hasNoData = 0;
    const double noData = GDALGetRasterNoDataValue( GDALGetRasterBand( mDataset, 1 ), &hasNoData );
    if ( hasNoData )
      mNoData = noData;
    mTilesX = ( mWidth + options.tileSize - 1 ) / options.tileSize;
    mTilesY = ( mHeight + options.tileSize - 1 ) / options.tileSize;
    mIndex.assign( static_cast<size_t>( mTilesX ) * mTilesY, nullptr );
  }

  Dem::~Dem()
  {
    if ( mDataset )
      GDALClose( mDataset );
  }

  Eigen::Vector2d Dem::metresPerUnit( double /* x: the scale does not vary with longitude */, double y ) const
  {
    if ( !mGeographic )
      return { 1.0, 1.0 };
    // Degrees: metres per degree of longitude shrink with latitude.
    const double latitude = std::clamp( y, -89.9, 89.9 ) * M_PI / 180.0;
    return { 111320.0 * std::cos( latitude ), 110574.0 };
  }

  const Dem::Tile *Dem::readTile( int tileX, int tileY ) const
  {
    const int T = mOptions.tileSize, H = mOptions.holeFillHalo;
    const int x0 = tileX * T, y0 = tileY * T;
    // Read the tile with a halo, so holes near its edge see their neighbours.
    // Filling runs H passes and a pass's error at the region's border moves
    // in one cell per pass, so cells at least H in from the border come out
    // as if the whole raster were filled: the tile and its extra last column
    // and row (the neighbours' first ones) agree with the neighbouring tiles.
    const int rx0 = std::max( 0, x0 - H ), ry0 = std::max( 0, y0 - H );
    const int rx1 = std::min( mWidth, x0 + T + 1 + H ), ry1 = std::min( mHeight, y0 + T + 1 + H );
    const int rw = rx1 - rx0, rh = ry1 - ry0;
    // (the region's buffer and an evicted tile's storage are reused: no allocation, no page faults per tile)
    std::vector<double> &region = mRegion;
    region.resize( static_cast<size_t>( rw ) * rh );
    if ( GDALRasterIO( GDALGetRasterBand( static_cast<GDALDatasetH>( mDataset ), 1 ), GF_Read, rx0, ry0, rw, rh, region.data(), rw, rh, GDT_Float64, 0, 0 ) != CE_None )
      throw std::runtime_error( std::string( "reading the DEM failed: " ) + CPLGetLastErrorMsg() );
    long empty = 0;
    for ( double &v : region )
      if ( !std::isfinite( v ) || ( mNoData && v == *mNoData ) )
      {
        v = kNaN;
        ++empty;
      }

    // The paper's filling: an empty cell takes the mean of its present
    // neighbours in X and Y; repeated inward, one ring per pass (none where
    // nothing is empty: most tiles of most DEMs).
    long filledInTile = 0;
    for ( int pass = 0; pass < H && empty > 0; ++pass )
    {
      std::vector<double> &next = mFillScratch;
      next = region;
      bool changed = false;
      for ( int r = 0; r < rh; ++r )
        for ( int c = 0; c < rw; ++c )
        {
          const size_t i = static_cast<size_t>( r ) * rw + c;
          if ( !std::isnan( region[i] ) )
            continue;
          double sum = 0.0;
          int n = 0;
          const int dc[4] = { -1, 1, 0, 0 }, dr[4] = { 0, 0, -1, 1 };
          for ( int k = 0; k < 4; ++k )
          {
            const int cc = c + dc[k], rr = r + dr[k];
            if ( cc < 0 || rr < 0 || cc >= rw || rr >= rh )
              continue;
            const double v = region[static_cast<size_t>( rr ) * rw + cc];
            if ( !std::isnan( v ) )
            {
              sum += v;
              ++n;
            }
          }
          if ( n > 0 )
          {
            next[i] = sum / n;
            changed = true;
            --empty;
            const int col = rx0 + c, row = ry0 + r;
            if ( col >= x0 && col < x0 + T && row >= y0 && row < y0 + T )
              ++filledInTile;
          }
        }
      region.swap( next );
      if ( !changed )
        break;
    }
    mFilledCells += filledInTile;

    // the least recently used tile gives way when the cache is full
    std::unique_ptr<Tile> t;
    size_t slot = mCache.size();
    if ( mCache.size() >= mOptions.cacheTiles )
    {
      slot = static_cast<size_t>( std::min_element( mCache.begin(), mCache.end(), []( const auto & a, const auto & b ) { return a->lastUse < b->lastUse; } ) - mCache.begin() );
      mIndex[mCache[slot]->index] = nullptr;
      t = std::move( mCache[slot] );
    }
    else
      t = std::make_unique<Tile>();
    const int stride = T + 1;
    t->vertices.assign( static_cast<size_t>( stride ) * stride, std::numeric_limits<float>::quiet_NaN() );
    for ( int row = y0; row <= std::min( y0 + T, mHeight - 1 ); ++row )
      for ( int col = x0; col <= std::min( x0 + T, mWidth - 1 ); ++col )
        t->vertices[static_cast<size_t>( row - y0 ) * stride + ( col - x0 )] = static_cast<float>( region[static_cast<size_t>( row - ry0 ) * rw + ( col - rx0 )] );

    // Block maxima over the corners of each block's cells; blocks with holes
    // take the tile's highest valid height (+inf if it has none).
    const int B = kBlockSize, blocks = T / B;
    t->blockMax.assign( static_cast<size_t>( blocks ) * blocks, 0.0f );
    std::vector<char> blockHasHole( t->blockMax.size(), 0 );
    float tileMax = -std::numeric_limits<float>::infinity();
    bool tileHasHole = false;
    for ( int by = 0; by < blocks; ++by )
      for ( int bx = 0; bx < blocks; ++bx )
      {
        float m = -std::numeric_limits<float>::infinity();
        bool hole = false, anyCell = false;
        for ( int r = by * B; r <= by * B + B && y0 + r < mHeight; ++r )
          for ( int c = bx * B; c <= bx * B + B && x0 + c < mWidth; ++c )
          {
            anyCell = true;
            const float v = t->vertices[static_cast<size_t>( r ) * stride + c];
            if ( std::isnan( v ) )
              hole = true;
            else
              m = std::max( m, v );
          }
        const size_t k = static_cast<size_t>( by ) * blocks + bx;
        t->blockMax[k] = m;
        blockHasHole[k] = hole && anyCell;
        tileHasHole = tileHasHole || blockHasHole[k];
        tileMax = std::max( tileMax, m );
      }
    if ( tileHasHole && !std::isfinite( tileMax ) )
      tileMax = std::numeric_limits<float>::infinity();
    for ( size_t k = 0; k < t->blockMax.size(); ++k )
      if ( blockHasHole[k] )
        t->blockMax[k] = tileMax;
    t->maxHeight = tileMax;

    t->index = static_cast<size_t>( tileY ) * mTilesX + tileX;
    t->lastUse = ++mClock;
    Tile *result = t.get();
    if ( slot < mCache.size() )
      mCache[slot] = std::move( t );
    else
      mCache.push_back( std::move( t ) );
    mIndex[result->index] = result;
    return result;
  }

  std::optional<double> Dem::heightAt( double x, double y ) const
  {
    return heightAtPixel( mInverse[0] + mInverse[1] * x + mInverse[2] * y, mInverse[3] + mInverse[4] * x + mInverse[5] * y );
  }

  std::optional<double> Dem::heightAtPixel( double px, double py ) const
  {
    // Pixel coordinates (corner convention) to cell-centre coordinates.
    const double u = px - 0.5, v = py - 0.5;
    if ( !( u >= 0.0 && v >= 0.0 && u <= mWidth - 1 && v <= mHeight - 1 ) )
      return std::nullopt;
    const int i = std::min( static_cast<int>( u ), mWidth - 2 ), j = std::min( static_cast<int>( v ), mHeight - 2 );
    const double fu = u - i, fv = v - j;
    // The tile holding cell (i, j) also holds its right and lower corners.
    const int T = mOptions.tileSize;
    const Tile *t = tile( i / T, j / T );
    const float *corner = t->vertices.data() + static_cast<size_t>( j % T ) * ( T + 1 ) + ( i % T );
    const double h00 = corner[0], h10 = corner[1], h01 = corner[T + 1], h11 = corner[T + 2];
    const double h = ( h00 * ( 1 - fu ) + h10 * fu ) * ( 1 - fv ) + ( h01 * ( 1 - fu ) + h11 * fu ) * fv;
    if ( std::isnan( h ) )
      return std::nullopt;
    return h;
  }

} // namespace geostation
