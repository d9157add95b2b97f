/***************************************************************************
  dem.cpp - a digital elevation model read through GDAL
 ***************************************************************************/
#include "dem/dem.h"
#include "io/rasterfile.h"

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
    /**
     * Beyond this (metres or the DEM's height unit) a value is no height but
     * an undeclared nodata sentinel, such as float32's -3.4e38 that many
     * DEMs use without saying so: treated as a hole.
     */
    constexpr double kMaxAbsHeight = 1.0e6;
  }

  Dem::Dem( const std::string &path, const DemOptions &options )
    : mOptions( options )
  {
    if ( options.tileSize < kBlockSize || options.tileSize % kBlockSize != 0 || options.holeFillHalo < 0 || options.cacheTiles < 9 )
      throw std::invalid_argument( "DEM options: tiles of a multiple of 8 cells, a non-negative halo and at least 9 cached tiles" );
    if ( options.bridgeHolesUpToCells < 0 || options.bridgeHolesUpToCells > 4096 || !( options.bridgeSigmaPerMetre >= 0.0 ) )
      throw std::invalid_argument( "DEM options: holes are bridged up to 0 (none) to 4096 cells across, with a non-negative sigma per metre" );
    registerGdalDrivers();
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
    // the inverse must be finite too (a denormal cell size inverts to infinity), and cells of more than 1000 km or an origin
    // beyond 1e10 are no terrain model (their arithmetic overflows)
    const auto finite = []( const std::array<double, 6> &g ) { return std::all_of( g.begin(), g.end(), []( double v ) { return std::isfinite( v ); } ); };
    if ( GDALGetGeoTransform( mDataset, mGeoTransform.data() ) != CE_None || !GDALInvGeoTransform( mGeoTransform.data(), mInverse.data() ) ||
         !finite( mGeoTransform ) || !finite( mInverse ) || std::hypot( mGeoTransform[1], mGeoTransform[4] ) < 1e-9 || std::hypot( mGeoTransform[2], mGeoTransform[5] ) < 1e-9 ||
         std::hypot( mGeoTransform[1], mGeoTransform[4] ) > 1e6 || std::hypot( mGeoTransform[2], mGeoTransform[5] ) > 1e6 || std::abs( mGeoTransform[0] ) > 1e10 ||
         std::abs( mGeoTransform[3] ) > 1e10 )
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
    // integers up to 32 bits are exact as floats within kMaxAbsHeight (beyond it, holes either way)
    switch ( GDALGetRasterDataType( GDALGetRasterBand( mDataset, 1 ) ) )
    {
      case GDT_Byte:
      case GDT_UInt16:
      case GDT_Int16:
      case GDT_UInt32:
      case GDT_Int32:
      case GDT_Float32:
        mCellsExactAsFloat = true;
        break;
      default:
        mCellsExactAsFloat = false;
    }
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

  namespace
  {
    /**
     * The paper's filling: an empty (NaN) cell takes the mean of its present
     * neighbours in X and Y; repeated inward, one ring per pass, at most
     * `passes` (none where nothing is empty: most tiles of most DEMs).
     * `region` is rw x rh cells from column rx0, row ry0; returns the cells
     * filled inside the tile of T x T cells from (x0, y0).
     */
    long fillHoles( std::vector<double> &region, std::vector<double> &next, int rx0, int ry0, int rw, int rh, long empty, int passes, int x0, int y0, int T )
    {
      long filledInTile = 0;
      for ( int pass = 0; pass < passes && empty > 0; ++pass )
      {
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
      return filledInTile;
    }
  }

  long Dem::readRegion( int x0, int y0, int halo, Region &at, std::vector<double> *original ) const
  {
    const int T = mOptions.tileSize;
    at.x0 = std::max( 0, x0 - halo );
    at.y0 = std::max( 0, y0 - halo );
    at.width = std::min( mWidth, x0 + T + 1 + halo ) - at.x0;
    at.height = std::min( mHeight, y0 + T + 1 + halo ) - at.y0;
    std::vector<double> &region = mRegion;
    region.resize( static_cast<size_t>( at.width ) * at.height );
    if ( GDALRasterIO( GDALGetRasterBand( static_cast<GDALDatasetH>( mDataset ), 1 ), GF_Read, at.x0, at.y0, at.width, at.height, region.data(), at.width, at.height,
                       GDT_Float64, 0, 0 ) != CE_None )
      throw std::runtime_error( std::string( "reading the DEM failed: " ) + CPLGetLastErrorMsg() );
    long empty = 0;
    for ( double &v : region )
      if ( !std::isfinite( v ) || ( mNoData && v == *mNoData ) || std::abs( v ) > kMaxAbsHeight )
      {
        v = kNaN;
        ++empty;
      }
    if ( original )
      *original = region;
    at.filledInTile = fillHoles( region, mFillScratch, at.x0, at.y0, at.width, at.height, empty, mOptions.holeFillHalo, x0, y0, T );
    long left = 0;
    for ( int row = y0; row <= std::min( y0 + T, mHeight - 1 ); ++row )
      for ( int col = x0; col <= std::min( x0 + T, mWidth - 1 ); ++col )
        left += std::isnan( region[static_cast<size_t>( row - at.y0 ) * at.width + ( col - at.x0 )] ) ? 1 : 0;
    return left;
  }

  void Dem::setBlockMaxima( Tile &t, int x0, int y0, bool mayHaveHoles ) const
  {
    // Block maxima over the corners of each block's cells; blocks with holes
    // take the tile's highest valid height (+inf if it has none).
    const int B = kBlockSize, blocks = mOptions.tileSize / B, stride = mOptions.tileSize + 1;
    t.blockMax.assign( static_cast<size_t>( blocks ) * blocks, 0.0f );
    if ( !mayHaveHoles )
    {
      // every cell in the DEM holds a height: the maxima of each column over a block's rows, then over its columns
      const int rows = std::min( mOptions.tileSize, mHeight - 1 - y0 ) + 1, cols = std::min( mOptions.tileSize, mWidth - 1 - x0 ) + 1;
      std::vector<float> &columnMax = mColumnMax;
      columnMax.resize( static_cast<size_t>( cols ) );
      float tileMax = -std::numeric_limits<float>::infinity();
      for ( int by = 0; by < blocks; ++by )
      {
        std::fill( columnMax.begin(), columnMax.end(), -std::numeric_limits<float>::infinity() );
        for ( int r = by * B; r <= std::min( by * B + B, rows - 1 ); ++r )
        {
          const float *row = t.vertices.data() + static_cast<size_t>( r ) * stride;
          for ( int c = 0; c < cols; ++c )
            columnMax[c] = std::max( columnMax[c], row[c] );
        }
        for ( int bx = 0; bx < blocks; ++bx )
        {
          float m = -std::numeric_limits<float>::infinity();
          for ( int c = bx * B; c <= std::min( bx * B + B, cols - 1 ); ++c )
            m = std::max( m, columnMax[c] );
          t.blockMax[static_cast<size_t>( by ) * blocks + bx] = m;
          tileMax = std::max( tileMax, m );
        }
      }
      t.maxHeight = tileMax;
      return;
    }
    std::vector<char> blockHasHole( t.blockMax.size(), 0 );
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
            const float v = t.vertices[static_cast<size_t>( r ) * stride + c];
            if ( std::isnan( v ) )
              hole = true;
            else
              m = std::max( m, v );
          }
        const size_t k = static_cast<size_t>( by ) * blocks + bx;
        t.blockMax[k] = m;
        blockHasHole[k] = hole && anyCell;
        tileHasHole = tileHasHole || blockHasHole[k];
        tileMax = std::max( tileMax, m );
      }
    if ( tileHasHole && !std::isfinite( tileMax ) )
      tileMax = std::numeric_limits<float>::infinity();
    for ( size_t k = 0; k < t.blockMax.size(); ++k )
      if ( blockHasHole[k] )
        t.blockMax[k] = tileMax;
    t.maxHeight = tileMax;
  }

  bool Dem::readTileCells( int x0, int y0, Tile &t ) const
  {
    if ( !mCellsExactAsFloat )
      return false;
    const int T = mOptions.tileSize, stride = T + 1;
    const int cols = std::min( x0 + T, mWidth - 1 ) - x0 + 1, rows = std::min( y0 + T, mHeight - 1 ) - y0 + 1;
    t.vertices.resize( static_cast<size_t>( stride ) * stride );
    if ( GDALRasterIO( GDALGetRasterBand( static_cast<GDALDatasetH>( mDataset ), 1 ), GF_Read, x0, y0, cols, rows, t.vertices.data(), cols, rows, GDT_Float32,
                       sizeof( float ), static_cast<GSpacing>( stride * sizeof( float ) ) ) != CE_None )
      throw std::runtime_error( std::string( "reading the DEM failed: " ) + CPLGetLastErrorMsg() );
    for ( int r = 0; r < rows; ++r )
    {
      const float *row = t.vertices.data() + static_cast<size_t>( r ) * stride;
      for ( int c = 0; c < cols; ++c )
        if ( !std::isfinite( row[c] ) || ( mNoData && row[c] == *mNoData ) || std::abs( row[c] ) > kMaxAbsHeight )
          return false;
    }
    // beyond the DEM (the last tiles' extra column and row)
    for ( int r = 0; r < stride; ++r )
      for ( int c = r < rows ? cols : 0; c < stride; ++c )
        t.vertices[static_cast<size_t>( r ) * stride + c] = std::numeric_limits<float>::quiet_NaN();
    return true;
  }

  const Dem::Tile *Dem::readTile( int tileX, int tileY ) const
  {
    const int T = mOptions.tileSize, H = mOptions.holeFillHalo;
    const int x0 = tileX * T, y0 = tileY * T;
    const size_t index = static_cast<size_t>( tileY ) * mTilesX + tileX;

    // the least recently used tile gives way when the cache is full (its storage is reused: no allocation, no
    // page faults per tile); a tile whose read throws is left out of the index, as the least recently used
    Tile *t = nullptr;
    std::unique_ptr<Tile> fresh;
    if ( mCache.size() >= mOptions.cacheTiles )
    {
      t = std::min_element( mCache.begin(), mCache.end(), []( const auto & a, const auto & b ) { return a->lastUse < b->lastUse; } )->get();
      if ( t->index < mIndex.size() && mIndex[t->index] == t )
        mIndex[t->index] = nullptr;
      t->index = mIndex.size();
      t->lastUse = 0;
    }
    else
    {
      fresh = std::make_unique<Tile>();
      t = fresh.get();
    }

    if ( readTileCells( x0, y0, *t ) )
    {
      // no holes: nothing to fill or bridge, so no halo is needed
      t->bridgeSigma.clear();
      setBlockMaxima( *t, x0, y0, false );
    }
    else
    {
      // Read the tile with a halo, so holes near its edge see their neighbours.
      // Filling runs H passes and a pass's error at the region's border moves
      // in one cell per pass, so cells at least H in from the border come out
      // as if the whole raster were filled: the tile and its extra last column
      // and row (the neighbours' first ones) agree with the neighbouring tiles.
      Region at;
      long leftEmpty = readRegion( x0, y0, H, at, nullptr );
      // holes too large to fill: bridged where asked, from a region wide enough to hold their rims (the fill
      // gives the same cells from it: its reach is the smaller halo)
      const int bridge = mOptions.bridgeHolesUpToCells;
      std::vector<float> bridgeSigma;
      if ( bridge > 0 && leftEmpty > 0 )
      {
        std::vector<double> original; // the region as read, where holes are bridged
        leftEmpty = readRegion( x0, y0, std::max( bridge, H ), at, &original );
        bridgeSigma = bridgeHoles( mRegion, original, at.x0, at.y0, at.width, at.height, x0, y0 );
      }
      mFilledCells += at.filledInTile;
      const int stride = T + 1;
      t->vertices.assign( static_cast<size_t>( stride ) * stride, std::numeric_limits<float>::quiet_NaN() );
      for ( int row = y0; row <= std::min( y0 + T, mHeight - 1 ); ++row )
        for ( int col = x0; col <= std::min( x0 + T, mWidth - 1 ); ++col )
          t->vertices[static_cast<size_t>( row - y0 ) * stride + ( col - x0 )] = static_cast<float>( mRegion[static_cast<size_t>( row - at.y0 ) * at.width + ( col - at.x0 )] );
      t->bridgeSigma = std::move( bridgeSigma );
      setBlockMaxima( *t, x0, y0, true );
    }

    ++mTileReads;
    t->index = index;
    t->lastUse = ++mClock;
    if ( fresh )
      mCache.push_back( std::move( fresh ) );
    mIndex[index] = t;
    return t;
  }

  std::vector<float> Dem::bridgeHoles( std::vector<double> &region, const std::vector<double> &original, int rx0, int ry0, int rw, int rh, int x0, int y0 ) const
  {
    const int T = mOptions.tileSize, stride = T + 1, limit = mOptions.bridgeHolesUpToCells;
    const int cols = std::min( x0 + T, mWidth - 1 ) - x0 + 1, rows = std::min( y0 + T, mHeight - 1 ) - y0 + 1;
    // the cells' size on the ground at the tile's centre (m)
    const double cx = x0 + 0.5 * cols, cy = y0 + 0.5 * rows;
    const Eigen::Vector2d perUnit = metresPerUnit( mGeoTransform[0] + cx * mGeoTransform[1] + cy * mGeoTransform[2], mGeoTransform[3] + cx * mGeoTransform[4] + cy * mGeoTransform[5] );
    const double cellX = std::hypot( mGeoTransform[1], mGeoTransform[4] ) * perUnit.x(), cellY = std::hypot( mGeoTransform[2], mGeoTransform[5] ) * perUnit.y();
    const auto index = [&]( int col, int row ) { return static_cast<size_t>( row - ry0 ) * rw + ( col - rx0 ); };

    // The large holes: the cells of every hole (as read) that the fill left partly empty, whole - the fill's
    // rings included, which are the least sure part of it.
    std::vector<char> large( region.size(), 0 );
    std::vector<size_t> stack;
    for ( size_t i = 0; i < region.size(); ++i )
      if ( std::isnan( region[i] ) && !large[i] )
      {
        large[i] = 1;
        stack.push_back( i );
        while ( !stack.empty() )
        {
          const size_t k = stack.back();
          stack.pop_back();
          const int c = static_cast<int>( k % rw ), r = static_cast<int>( k / rw );
          const int dc[4] = { -1, 1, 0, 0 }, dr[4] = { 0, 0, -1, 1 };
          for ( int n = 0; n < 4; ++n )
          {
            const int cc = c + dc[n], rr = r + dr[n];
            if ( cc < 0 || rr < 0 || cc >= rw || rr >= rh )
              continue;
            const size_t m = static_cast<size_t>( rr ) * rw + cc;
            if ( !large[m] && std::isnan( original[m] ) )
            {
              large[m] = 1;
              stack.push_back( m );
            }
          }
        }
      }

    // Along rows, then along columns: each run of a large hole's cells no longer than the limit, between two
    // cells of data, is interpolated linearly; its sigma is what the terrain's curvature just outside the
    // rims (second differences over 3 cells) makes of a straight line across (kappa d1 d2 / 2), and at least
    // bridgeSigmaPerMetre times the distance to the nearer rim.
    const size_t n = static_cast<size_t>( stride ) * stride;
    std::vector<double> height[2] = { std::vector<double>( n, kNaN ), std::vector<double>( n, kNaN ) };
    std::vector<double> sigmaOf[2] = { std::vector<double>( n, 0.0 ), std::vector<double>( n, 0.0 ) };
    const auto bridgeLine = [&]( int axis, int fixed )
    {
      const bool byRow = axis == 0;
      const int from = byRow ? rx0 : ry0, to = byRow ? rx0 + rw : ry0 + rh;
      const double cell = byRow ? cellX : cellY;
      const auto cellOf = [&]( int k ) { return byRow ? index( k, fixed ) : index( fixed, k ); };
      for ( int k = from; k < to; )
      {
        if ( !large[cellOf( k )] )
        {
          ++k;
          continue;
        }
        int end = k;
        while ( end < to && large[cellOf( end )] )
          ++end;
        // the hole from k to end - 1, its rims at k - 1 and end
        if ( k > from && end < to && end - k <= limit && !std::isnan( original[cellOf( k - 1 )] ) && !std::isnan( original[cellOf( end )] ) )
        {
          const double a = original[cellOf( k - 1 )], b = original[cellOf( end )];
          // curvature outside either rim (1/m)
          double kappa = 0.0;
          constexpr int s = 3;
          for ( const int side : { -1, 1 } )
          {
            const int rim = side < 0 ? k - 1 : end;
            const int p1 = rim + side * s, p2 = rim + 2 * side * s;
            if ( p2 < from || p2 >= to )
              continue;
            const double h0 = original[cellOf( rim )], h1 = original[cellOf( p1 )], h2 = original[cellOf( p2 )];
            if ( !std::isnan( h1 ) && !std::isnan( h2 ) )
              kappa = std::max( kappa, std::abs( h0 - 2.0 * h1 + h2 ) / ( s * cell * s * cell ) );
          }
          for ( int m = k; m < end; ++m )
          {
            const int col = byRow ? m : fixed, row = byRow ? fixed : m;
            if ( col < x0 || row < y0 || col >= x0 + cols || row >= y0 + rows )
              continue;
            const double d1 = ( m - ( k - 1 ) ) * cell, d2 = ( end - m ) * cell;
            const size_t i = static_cast<size_t>( row - y0 ) * stride + ( col - x0 );
            height[axis][i] = a + d1 / ( d1 + d2 ) * ( b - a );
            sigmaOf[axis][i] = std::max( 0.5 * kappa * d1 * d2, mOptions.bridgeSigmaPerMetre * std::min( d1, d2 ) );
          }
        }
        k = end;
      }
    };
    for ( int row = y0; row < y0 + rows; ++row )
      bridgeLine( 0, row );
    for ( int col = x0; col < x0 + cols; ++col )
      bridgeLine( 1, col );

    std::vector<float> sigma;
    for ( int row = y0; row < y0 + rows; ++row )
      for ( int col = x0; col < x0 + cols; ++col )
      {
        const size_t i = static_cast<size_t>( row - y0 ) * stride + ( col - x0 );
        const bool r = !std::isnan( height[0][i] ), c = !std::isnan( height[1][i] );
        if ( !r && !c )
          continue;
        // (both: their mean, its sigma also half their difference)
        const double h = r && c ? 0.5 * ( height[0][i] + height[1][i] ) : r ? height[0][i] : height[1][i];
        const double s = r && c ? std::hypot( 0.5 * ( height[0][i] - height[1][i] ), 0.5 * ( sigmaOf[0][i] + sigmaOf[1][i] ) ) : r ? sigmaOf[0][i] : sigmaOf[1][i];
        if ( sigma.empty() )
          sigma.assign( n, 0.0f );
        sigma[i] = static_cast<float>( std::max( s, 1e-6 ) );
        region[index( col, row )] = h;
        if ( col < x0 + T && row < y0 + T )
          ++mBridgedCells;
      }
    return sigma;
  }

  bool Dem::cellAt( double px, double py, const Tile *&t, size_t &corner, double &fu, double &fv ) const
  {
    // Pixel coordinates (corner convention) to cell-centre coordinates.
    const double u = px - 0.5, v = py - 0.5;
    if ( !( u >= 0.0 && v >= 0.0 && u <= mWidth - 1 && v <= mHeight - 1 ) )
      return false;
    const int i = std::min( static_cast<int>( u ), mWidth - 2 ), j = std::min( static_cast<int>( v ), mHeight - 2 );
    fu = u - i;
    fv = v - j;
    // The tile holding cell (i, j) also holds its right and lower corners.
    const int T = mOptions.tileSize;
    t = tile( i / T, j / T );
    corner = static_cast<size_t>( j % T ) * ( T + 1 ) + ( i % T );
    return t != nullptr;
  }

  std::optional<double> Dem::bridgeSigmaAt( double x, double y ) const
  {
    const Tile *t = nullptr;
    size_t corner = 0;
    double fu = 0.0, fv = 0.0;
    if ( !cellAt( mInverse[0] + mInverse[1] * x + mInverse[2] * y, mInverse[3] + mInverse[4] * x + mInverse[5] * y, t, corner, fu, fv ) )
      return std::nullopt;
    const int T = mOptions.tileSize;
    const float *h = t->vertices.data() + corner;
    if ( std::isnan( h[0] ) || std::isnan( h[1] ) || std::isnan( h[T + 1] ) || std::isnan( h[T + 2] ) )
      return std::nullopt;
    if ( t->bridgeSigma.empty() )
      return 0.0;
    const float *s = t->bridgeSigma.data() + corner;
    return static_cast<double>( std::max( { s[0], s[1], s[T + 1], s[T + 2] } ) );
  }

  std::optional<double> Dem::heightAt( double x, double y ) const
  {
    return heightAtPixel( mInverse[0] + mInverse[1] * x + mInverse[2] * y, mInverse[3] + mInverse[4] * x + mInverse[5] * y );
  }

  std::optional<double> Dem::heightAtPixel( double px, double py ) const
  {
    const Tile *t = nullptr;
    size_t corner = 0;
    double fu = 0.0, fv = 0.0;
    if ( !cellAt( px, py, t, corner, fu, fv ) )
      return std::nullopt;
    const int T = mOptions.tileSize;
    const float *c = t->vertices.data() + corner;
    const double h00 = c[0], h10 = c[1], h01 = c[T + 1], h11 = c[T + 2];
    const double h = ( h00 * ( 1 - fu ) + h10 * fu ) * ( 1 - fv ) + ( h01 * ( 1 - fu ) + h11 * fu ) * fv;
    if ( std::isnan( h ) )
      return std::nullopt;
    return h;
  }

} // namespace geostation
