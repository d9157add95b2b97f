/***************************************************************************
  fuzzrasters.cpp - images and DEMs as they come from disk
  -------------------------------------------------------------------------
  raster: any bytes as an image file (TIFF, PNG, JPEG, ... whatever GDAL
  recognises) through readRaster(): std::invalid_argument with a message,
  or pixels of 1 or 3 channels, 8 or 16 bits, of a positive size; and
  through pixelSpaceSource(), as the Multiview opens a photo: the file
  itself, or a VRT of the same size in pixel space (no CRS, no GCPs),
  and an EXIF orientation tag of 1-8.
  dem: any bytes as a DEM through Dem (std::runtime_error with a message),
  then heights and a ray's intersection across the whole extent: every
  height finite, the intersection on the ray; a tile that cannot be read
  (a corrupt block) is std::runtime_error with a message too.

  Inputs are GDAL memory files (/vsimem/), so no disk is touched. Images
  that claim more than 16 Mpx are left out (a decompression bomb in a few
  bytes only measures the allocator).
 ***************************************************************************/
#include "fuzztarget.h"

#include <array>
#include <cmath>
#include <string>

#include <gdal.h>
#include <cpl_vsi.h>

#include "dem/dem.h"
#include "dem/demintersection.h"
#include "geometry/crs.h"
#include "io/photoimport.h"
#include "io/rasterfile.h"

namespace
{
  namespace fuzz = geostation::fuzz;

  //! The bytes as a GDAL memory file, removed when it goes out of scope.
  class MemoryFile
  {
    public:
      MemoryFile( const std::string &path, const std::uint8_t *data, std::size_t size )
        : mPath( path )
      {
        VSILFILE *file = VSIFileFromMemBuffer( mPath.c_str(), const_cast<GByte *>( data ), static_cast<vsi_l_offset>( size ), FALSE );
        VSIFCloseL( file );
      }
      ~MemoryFile() { VSIUnlink( mPath.c_str() ); }
      const std::string &path() const { return mPath; }

    private:
      std::string mPath;
  };

  //! Width x height as GDAL sees it before any pixel is read; 0 if it cannot open it.
  double claimedPixels( const std::string &path )
  {
    GDALDatasetH dataset = GDALOpen( path.c_str(), GA_ReadOnly );
    if ( !dataset )
      return 0.0;
    const double pixels = static_cast<double>( GDALGetRasterXSize( dataset ) ) * GDALGetRasterYSize( dataset );
    GDALClose( dataset );
    return pixels;
  }

  //! Heights over the extent and a ray from above its middle; throws std::runtime_error where a tile cannot be read.
  void sampleDem( const geostation::Dem &dem )
  {
    const std::array<double, 6> &g = dem.geoTransform();
    // heights on a 9 x 9 grid over the extent, and a bit beyond it
    for ( int i = -1; i <= 9; ++i )
      for ( int j = -1; j <= 9; ++j )
      {
        const double col = dem.width() * i / 8.0, row = dem.height() * j / 8.0;
        const double x = g[0] + col * g[1] + row * g[2], y = g[3] + col * g[4] + row * g[5];
        const std::optional<double> h = dem.heightAt( x, y );
        if ( h && !std::isfinite( *h ) )
          fuzz::violated( "a height that is not finite" );
        const std::optional<double> sigma = dem.bridgeSigmaAt( x, y );
        if ( sigma && !( *sigma >= 0.0 && std::isfinite( *sigma ) ) )
          fuzz::violated( "a bridged height's sigma that is not finite and >= 0" );
      }

    // a ray from 20 m above the middle, 60 degrees down
    if ( dem.isGeographic() )
    {
      fuzz::outcome( "geographic DEM " + std::to_string( dem.width() ) + " x " + std::to_string( dem.height() ) );
      return;
    }
    std::unique_ptr<geostation::CrsTransform> identity;
    try
    {
      identity = std::make_unique<geostation::CrsTransform>( dem.crsWkt(), dem.crsWkt() );
    }
    catch ( const std::invalid_argument & )
    {
      return; // a CRS PROJ reads but cannot relate to itself: nothing to intersect with
    }
    const double midCol = 0.5 * dem.width(), midRow = 0.5 * dem.height();
    const Eigen::Vector2d middle( g[0] + midCol * g[1] + midRow * g[2], g[3] + midCol * g[4] + midRow * g[5] );
    const double ground = dem.heightAt( middle.x(), middle.y() ).value_or( 0.0 );
    const geostation::Ray ray { Eigen::Vector3d( middle.x(), middle.y(), ground + 20.0 ), Eigen::Vector3d( 0.5, 0.0, -std::sqrt( 0.75 ) ) };
    if ( !ray.origin.allFinite() )
      return;
    geostation::DemIntersectionOptions rayOptions;
    rayOptions.maxRangeM = 10000.0;
    const geostation::DemIntersection hit = geostation::intersectRayWithDem( ray, dem, *identity, rayOptions );
    fuzz::outcome( "DEM " + std::to_string( dem.width() ) + " x " + std::to_string( dem.height() ) + ", ray: " + ( hit.hit() ? std::string( "hit" ) : hit.message ) );
    if ( hit.hit() )
    {
      const Eigen::Vector3d along = hit.point - ray.origin;
      const double offRay = ( along - along.dot( ray.direction ) * ray.direction ).norm();
      if ( !hit.point.allFinite() || offRay > 1e-3 * ( 1.0 + along.norm() ) )
        fuzz::violated( "a ray / DEM intersection off the ray or not finite" );
    }
    else if ( hit.message.empty() )
      fuzz::violated( "a ray that misses the DEM without a message" );
  }

  const double kMaxPixels = 16.0e6;

  //! The photo as the Multiview opens it: the file itself, or a pixel-space VRT of the same size (x = -col when mirrored).
  void checkPixelSpaceSource( const std::string &path )
  {
    const std::string memoryPath = "/vsimem/fuzz-raster-pixels.vrt";
    int tag = 0;
    // as the Multiview asks: mirrored where the file is tagged so
    const std::string source = geostation::pixelSpaceSource( path, memoryPath, &tag, true );
    const double xStep = geostation::viewForExifOrientation( tag ).mirrored ? -1.0 : 1.0;
    if ( tag < 1 || tag > 8 )
      fuzz::violated( "pixelSpaceSource() gave an EXIF orientation tag outside 1-8" );
    if ( source == path )
      return;
    if ( source != memoryPath )
      fuzz::violated( "pixelSpaceSource() gave neither the file nor its memory path" );
    GDALDatasetH original = GDALOpen( path.c_str(), GA_ReadOnly ), view = GDALOpen( source.c_str(), GA_ReadOnly );
    std::array<double, 6> gt {};
    if ( !original || !view )
      fuzz::violated( "a pixel-space VRT written for a file that does not open again" );
    else if ( GDALGetRasterXSize( view ) != GDALGetRasterXSize( original ) || GDALGetRasterYSize( view ) != GDALGetRasterYSize( original ) )
      fuzz::violated( "a pixel-space VRT of another size than its file" );
    else if ( GDALGetGeoTransform( view, gt.data() ) != CE_None || gt != std::array<double, 6> { 0.0, xStep, 0.0, 0.0, 0.0, -1.0 } || GDALGetGCPCount( view ) != 0 ||
              std::string( GDALGetProjectionRef( view ) ) != "" )
      fuzz::violated( "a pixel-space VRT that is not in pixel space" );
    if ( view )
      GDALClose( view );
    if ( original )
      GDALClose( original );
    geostation::discardMemoryRaster( memoryPath );
    fuzz::outcome( "shown through a pixel-space VRT" );
  }

  struct QuietGdal
  {
    QuietGdal()
    {
      GDALAllRegister();
      CPLSetErrorHandler( CPLQuietErrorHandler );
    }
  };
}

GEOSTATION_FUZZ_TARGET( raster )
{
  static const QuietGdal quiet;
  const MemoryFile file( "/vsimem/fuzz-raster", data, size );
  if ( claimedPixels( file.path() ) > kMaxPixels )
    return 0;
  try
  {
    const geostation::RasterImage image = geostation::readRaster( file.path() );
    const int depth = image.pixels.depth();
    if ( image.pixels.empty() || ( image.pixels.channels() != 1 && image.pixels.channels() != 3 ) || ( depth != CV_8U && depth != CV_16U ) )
      fuzz::violated( "readRaster() gave pixels that are empty or not 1 or 3 channels of 8 or 16 bits" );
    fuzz::outcome( "read: " + std::to_string( image.pixels.cols ) + " x " + std::to_string( image.pixels.rows ) + " x " + std::to_string( image.pixels.channels() ) );
  }
  catch ( const std::invalid_argument &error )
  {
    fuzz::requireMessage( error );
  }
  checkPixelSpaceSource( file.path() );
  return 0;
}

GEOSTATION_FUZZ_TARGET( dem )
{
  static const QuietGdal quiet;
  const MemoryFile file( "/vsimem/fuzz-dem", data, size );
  if ( claimedPixels( file.path() ) > kMaxPixels )
    return 0;
  geostation::DemOptions options;
  options.tileSize = 16;
  options.holeFillHalo = 4;
  options.cacheTiles = 9;
  options.bridgeHolesUpToCells = 24;
  std::unique_ptr<geostation::Dem> dem;
  try
  {
    dem = std::make_unique<geostation::Dem>( file.path(), options );
  }
  catch ( const std::runtime_error &error )
  {
    fuzz::requireMessage( error );
    return 0;
  }
  try
  {
    sampleDem( *dem );
  }
  catch ( const std::runtime_error &error )
  {
    fuzz::requireMessage( error );
  }
  return 0;
}
