/***************************************************************************
  rasterfile.cpp - GDAL raster <-> cv::Mat with georeferencing
 ***************************************************************************/
#include "io/rasterfile.h"

#include <cstdio>
#include <filesystem>
#include <memory>
#include <stdexcept>
#include <vector>

#include <cpl_conv.h>
#include <cpl_error.h>
#include <cpl_vsi.h>
#include <gdal.h>

namespace geostation
{
  namespace
  {
    struct DatasetCloser
    {
      void operator()( void *ds ) const { GDALClose( ds ); }
    };
  }

  RasterImage readRaster( const std::string &path )
  {
    GDALAllRegister();
    CPLPushErrorHandler( CPLQuietErrorHandler );
    std::unique_ptr<void, DatasetCloser> ds( GDALOpen( path.c_str(), GA_ReadOnly ) );
    CPLPopErrorHandler();
    if ( !ds )
      throw std::invalid_argument( "cannot open the raster " + path );
    const int bands = GDALGetRasterCount( ds.get() );
    if ( bands != 1 && bands != 3 )
      throw std::invalid_argument( "the raster " + path + " has " + std::to_string( bands ) + " bands; 1 (grey) or 3 (RGB) are supported" );
    const GDALDataType type = GDALGetRasterDataType( GDALGetRasterBand( ds.get(), 1 ) );
    if ( type != GDT_Byte && type != GDT_UInt16 )
      throw std::invalid_argument( "the raster " + path + " is " + GDALGetDataTypeName( type ) + "; 8- and 16-bit unsigned images are supported" );
    const int width = GDALGetRasterXSize( ds.get() ), height = GDALGetRasterYSize( ds.get() );
    RasterImage image;
    image.pixels = cv::Mat( height, width, CV_MAKETYPE( type == GDT_Byte ? CV_8U : CV_16U, bands ) );
    std::vector<int> bandMap( bands );
    for ( int b = 0; b < bands; ++b )
      bandMap[b] = b + 1;
    const int pixelBytes = static_cast<int>( image.pixels.elemSize() );
    if ( GDALDatasetRasterIO( ds.get(), GF_Read, 0, 0, width, height, image.pixels.data, width, height, type, bands, bandMap.data(), pixelBytes,
                              static_cast<GSpacing>( image.pixels.step[0] ), static_cast<GSpacing>( image.pixels.elemSize1() ) ) != CE_None )
      throw std::invalid_argument( "cannot read the raster " + path );
    std::array<double, 6> gt;
    if ( GDALGetGeoTransform( ds.get(), gt.data() ) == CE_None )
      image.geoTransform = gt;
    if ( const char *wkt = GDALGetProjectionRef( ds.get() ) )
      image.crsWkt = wkt;
    int hasNoData = 0;
    const double noData = GDALGetRasterNoDataValue( GDALGetRasterBand( ds.get(), 1 ), &hasNoData );
    if ( hasNoData )
      image.noData = noData;
    return image;
  }

  void writeGeoTiffLike( const std::string &path, const cv::Mat &pixels, const RasterImage &like )
  {
    GDALAllRegister();
    // an in-memory raster (/vsimem/, e.g. an enhanced view) is written in place, uncompressed
    const bool memory = path.rfind( "/vsimem/", 0 ) == 0;
    const std::string temporary = memory ? path : path + ".tmp-write.tif";
    const GDALDataType type = pixels.depth() == CV_8U ? GDT_Byte : GDT_UInt16;
    const int bands = pixels.channels();
    std::vector<const char *> creation;
    if ( bands == 3 )
      creation = { "PHOTOMETRIC=RGB", "INTERLEAVE=PIXEL" };
    creation.push_back( "TILED=YES" );
    if ( !memory )
      creation.insert( creation.end(), { "COMPRESS=DEFLATE", "BIGTIFF=IF_SAFER" } );
    creation.push_back( nullptr );
    {
      std::unique_ptr<void, DatasetCloser> ds( GDALCreate( GDALGetDriverByName( "GTiff" ), temporary.c_str(), pixels.cols, pixels.rows, bands, type,
                                              const_cast<char **>( creation.data() ) ) );
      if ( !ds )
        throw std::runtime_error( "cannot create " + path + " (is the folder writable?)" );
      if ( like.geoTransform )
      {
        std::array<double, 6> gt = *like.geoTransform;
        GDALSetGeoTransform( ds.get(), gt.data() );
      }
      if ( !like.crsWkt.empty() )
        GDALSetProjection( ds.get(), like.crsWkt.c_str() );
      if ( like.noData )
        for ( int b = 1; b <= bands; ++b )
          GDALSetRasterNoDataValue( GDALGetRasterBand( ds.get(), b ), *like.noData );
      std::vector<int> bandMap( bands );
      for ( int b = 0; b < bands; ++b )
        bandMap[b] = b + 1;
      if ( GDALDatasetRasterIO( ds.get(), GF_Write, 0, 0, pixels.cols, pixels.rows, const_cast<uchar *>( pixels.data ), pixels.cols, pixels.rows, type, bands,
                                bandMap.data(), static_cast<int>( pixels.elemSize() ), static_cast<GSpacing>( pixels.step[0] ),
                                static_cast<GSpacing>( pixels.elemSize1() ) ) != CE_None )
      {
        ds.reset();
        std::remove( temporary.c_str() );
        throw std::runtime_error( "writing " + path + " failed (disk full?)" );
      }
      if ( static_cast<long>( pixels.cols ) * pixels.rows > 4'000'000 )
      {
        int levels[] = { 2, 4, 8, 16 };
        if ( GDALBuildOverviews( ds.get(), "AVERAGE", 4, levels, 0, nullptr, nullptr, nullptr ) != CE_None )
          CPLErrorReset(); // overviews are a convenience; the image itself is written
      }
    }
    if ( memory )
      return;
    std::error_code ec;
    std::filesystem::rename( temporary, path, ec );
    if ( ec )
    {
      std::remove( temporary.c_str() );
      throw std::runtime_error( "cannot replace " + path + ": " + ec.message() );
    }
  }

  void discardMemoryRaster( const std::string &path )
  {
    if ( path.rfind( "/vsimem/", 0 ) == 0 )
      VSIUnlink( path.c_str() );
  }

} // namespace geostation
