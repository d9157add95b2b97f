// Synthetic hilly terrain for DEM tests and benchmarks: an analytic surface
// (hills 12 m high, a gentle eastward rise) sampled at cell centres into a
// GeoTIFF, with optional nodata cells.
#ifndef GEOSTATION_TESTS_SYNTHETICTERRAIN_H
#define GEOSTATION_TESTS_SYNTHETICTERRAIN_H

#include <array>
#include <cmath>
#include <filesystem>
#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

#include <gdal.h>
#include <ogr_srs_api.h>
#include <unistd.h>

namespace syntheticterrain
{
  //! Top-left corner of the terrain in EPSG:32633.
  constexpr double kX0 = 400000.0, kY0 = 5000000.0;

  inline double height( double x, double y, double rise = 0.05 )
  {
    return 100.0 + 12.0 * std::sin( ( x - kX0 ) / 40.0 ) * std::cos( ( y - kY0 ) / 55.0 ) + rise * ( x - kX0 );
  }

  //! A temporary file path unique to this process.
  inline std::string tempPath( const std::string &name, const std::string &extension = ".tif" )
  {
    return ( std::filesystem::temp_directory_path() / ( "geostation-" + name + "-" + std::to_string( ::getpid() ) + extension ) ).string();
  }

  /**
   * Writes a Float32 GeoTIFF whose cell (c, r) holds value(x, y) at the cell
   * centre; `crs` may be null (no CRS); `hole(c, r)` marks nodata cells.
   */
  inline void writeDem( const std::string &path, const char *crs, const std::array<double, 6> &geoTransform, int width, int height,
                        const std::function<double( double, double )> &value, const std::function<bool( int, int )> &hole = nullptr,
                        GDALDataType type = GDT_Float32 )
  {
    GDALAllRegister();
    GDALDatasetH ds = GDALCreate( GDALGetDriverByName( "GTiff" ), path.c_str(), width, height, 1, type, nullptr );
    if ( !ds )
      throw std::runtime_error( "cannot create " + path );
    std::array<double, 6> gt = geoTransform;
    GDALSetGeoTransform( ds, gt.data() );
    if ( crs )
    {
      OGRSpatialReferenceH srs = OSRNewSpatialReference( nullptr );
      OSRSetFromUserInput( srs, crs );
      OSRSetAxisMappingStrategy( srs, OAMS_TRADITIONAL_GIS_ORDER );
      GDALSetSpatialRef( ds, srs );
      OSRDestroySpatialReference( srs );
    }
    GDALSetRasterNoDataValue( GDALGetRasterBand( ds, 1 ), -9999.0 );
    std::vector<float> row( width );
    for ( int r = 0; r < height; ++r )
    {
      for ( int c = 0; c < width; ++c )
      {
        const double x = gt[0] + ( c + 0.5 ) * gt[1], y = gt[3] + ( r + 0.5 ) * gt[5];
        row[c] = hole && hole( c, r ) ? -9999.0f : static_cast<float>( value( x, y ) );
      }
      if ( GDALRasterIO( GDALGetRasterBand( ds, 1 ), GF_Write, 0, r, width, 1, row.data(), width, 1, GDT_Float32, 0, 0 ) != CE_None )
        throw std::runtime_error( "cannot write " + path );
    }
    GDALClose( ds );
  }

  //! The standard test terrain: 2 m cells from (kX0, kY0), EPSG:32633.
  inline void writeTerrain( const std::string &path, int cells, double x0 = kX0, const char *crs = "EPSG:32633", double rise = 0.05,
                            const std::function<bool( int, int )> &hole = nullptr )
  {
    writeDem( path, crs, { x0, 2.0, 0.0, kY0, 0.0, -2.0 }, cells, cells, [rise]( double x, double y ) { return height( x, y, rise ); }, hole );
  }
}

#endif
