/***************************************************************************
  rasterfile.cpp - GDAL raster <-> cv::Mat with georeferencing
 ***************************************************************************/
#include "io/rasterfile.h"

#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <string>
#include <vector>

#include <cpl_conv.h>
#include <cpl_error.h>
#include <cpl_vsi.h>
#include <gdal.h>

#include "io/photoimport.h"

namespace geostation
{
  namespace
  {
    struct DatasetCloser
    {
      void operator()( void *ds ) const { GDALClose( ds ); }
    };

    GDALColorInterp interpretation( GDALDatasetH ds, int band )
    {
      return GDALGetRasterColorInterpretation( GDALGetRasterBand( ds, band ) );
    }

    /**
     * The bands that make the image: 1 (grey or palette) or 3 (RGB) as they
     * are; a last band that is alpha (grey + alpha, RGBA) is left out, as
     * is nothing else. Throws std::invalid_argument naming the layout.
     */
    int usedBands( GDALDatasetH ds, const std::string &path )
    {
      const int bands = GDALGetRasterCount( ds );
      if ( bands == 1 || bands == 3 )
        return bands;
      if ( ( bands == 2 || bands == 4 ) && interpretation( ds, bands ) == GCI_AlphaBand )
        return bands - 1;
      std::string layout;
      for ( int b = 1; b <= bands && b <= 8; ++b )
        layout += std::string( b > 1 ? ", " : "" ) + GDALGetColorInterpretationName( interpretation( ds, b ) );
      throw std::invalid_argument( "the raster " + path + " has " + std::to_string( bands ) + " bands (" + layout + ( bands > 8 ? ", ..." : "" ) +
                                   "); grey, RGB, and either with an alpha band are supported" );
    }

    //! The colour table of a palette image (one band of indices), nullptr for any other image.
    GDALColorTableH paletteOf( GDALDatasetH ds )
    {
      if ( GDALGetRasterCount( ds ) > 2 || interpretation( ds, 1 ) != GCI_PaletteIndex )
        return nullptr;
      GDALColorTableH table = GDALGetRasterColorTable( GDALGetRasterBand( ds, 1 ) );
      return table && GDALGetPaletteInterpretation( table ) == GPI_RGB ? table : nullptr;
    }

    /**
     * Palette indices (8 or 16 bits) as the colours they stand for: grey
     * when every entry is grey, RGB otherwise (8 bits; indices beyond the
     * table are black).
     */
    cv::Mat expandPalette( const cv::Mat &indices, GDALColorTableH table )
    {
      const int entries = GDALGetColorEntryCount( table );
      bool grey = true;
      for ( int i = 0; i < entries; ++i )
      {
        const GDALColorEntry *e = GDALGetColorEntry( table, i );
        grey = grey && e->c1 == e->c2 && e->c2 == e->c3;
      }
      cv::Mat colours( indices.rows, indices.cols, grey ? CV_8UC1 : CV_8UC3 );
      for ( int r = 0; r < indices.rows; ++r )
        for ( int c = 0; c < indices.cols; ++c )
        {
          const int index = indices.depth() == CV_8U ? indices.at<uchar>( r, c ) : indices.at<ushort>( r, c );
          const GDALColorEntry *e = index < entries ? GDALGetColorEntry( table, index ) : nullptr;
          const uchar red = e ? static_cast<uchar>( e->c1 ) : 0, green = e ? static_cast<uchar>( e->c2 ) : 0, blue = e ? static_cast<uchar>( e->c3 ) : 0;
          if ( grey )
            colours.at<uchar>( r, c ) = red;
          else
            colours.at<cv::Vec3b>( r, c ) = cv::Vec3b( red, green, blue );
        }
      return colours;
    }
  }

  namespace
  {
    std::unique_ptr<void, DatasetCloser> openRaster( const std::string &path )
    {
      registerGdalDrivers();
      CPLPushErrorHandler( CPLQuietErrorHandler );
      std::unique_ptr<void, DatasetCloser> ds( GDALOpen( path.c_str(), GA_ReadOnly ) );
      CPLPopErrorHandler();
      if ( !ds )
        throw std::invalid_argument( "cannot open the raster " + path );
      return ds;
    }

    //! The pixels `window` (or all) of an open raster, georeferencing kept.
    RasterImage readPixels( GDALDatasetH ds, const std::string &path, const std::optional<cv::Rect> &window )
    {
      const int bands = usedBands( ds, path );
      const GDALDataType type = GDALGetRasterDataType( GDALGetRasterBand( ds, 1 ) );
      if ( type != GDT_Byte && type != GDT_UInt16 )
        throw std::invalid_argument( "the raster " + path + " is " + GDALGetDataTypeName( type ) + "; 8- and 16-bit unsigned images are supported" );
      const cv::Rect all( 0, 0, GDALGetRasterXSize( ds ), GDALGetRasterYSize( ds ) );
      const cv::Rect read = window.value_or( all );
      if ( read.empty() || ( read & all ) != read )
        throw std::invalid_argument( "the window asked of " + path + " does not lie in the raster" );
      RasterImage image;
      image.pixels = cv::Mat( read.height, read.width, CV_MAKETYPE( type == GDT_Byte ? CV_8U : CV_16U, bands ) );
      std::vector<int> bandMap( bands );
      for ( int b = 0; b < bands; ++b )
        bandMap[b] = b + 1;
      const int pixelBytes = static_cast<int>( image.pixels.elemSize() );
      if ( GDALDatasetRasterIO( ds, GF_Read, read.x, read.y, read.width, read.height, image.pixels.data, read.width, read.height, type, bands, bandMap.data(),
                                pixelBytes, static_cast<GSpacing>( image.pixels.step[0] ), static_cast<GSpacing>( image.pixels.elemSize1() ) ) != CE_None )
        throw std::invalid_argument( "cannot read the raster " + path );
      if ( GDALColorTableH table = paletteOf( ds ) )
        image.pixels = expandPalette( image.pixels, table );
      std::array<double, 6> gt;
      if ( GDALGetGeoTransform( ds, gt.data() ) == CE_None )
        image.geoTransform = gt;
      if ( const char *wkt = GDALGetProjectionRef( ds ) )
        image.crsWkt = wkt;
      int hasNoData = 0;
      const double noData = GDALGetRasterNoDataValue( GDALGetRasterBand( ds, 1 ), &hasNoData );
      if ( hasNoData )
        image.noData = noData;
      return image;
    }
  }

  RasterImage readRaster( const std::string &path )
  {
    const auto ds = openRaster( path );
    return readPixels( ds.get(), path, std::nullopt );
  }

  void registerGdalDrivers()
  {
    static std::once_flag registered;
    std::call_once( registered, [] { GDALAllRegister(); } );
  }

  RasterImage readRasterWindow( const std::string &path, const cv::Rect &window )
  {
    const auto ds = openRaster( path );
    return readPixels( ds.get(), path, window );
  }

  cv::Size rasterSize( const std::string &path )
  {
    const auto ds = openRaster( path );
    return cv::Size( GDALGetRasterXSize( ds.get() ), GDALGetRasterYSize( ds.get() ) );
  }

  RasterReader::RasterReader( const std::string &path )
    : mPath( path )
  {
    auto ds = openRaster( path );
    mSize = cv::Size( GDALGetRasterXSize( ds.get() ), GDALGetRasterYSize( ds.get() ) );
    mEightBit = GDALGetRasterDataType( GDALGetRasterBand( ds.get(), 1 ) ) == GDT_Byte;
    mDataset = ds.release();
  }

  RasterReader::~RasterReader()
  {
    DatasetCloser()( mDataset );
  }

  RasterImage RasterReader::read( const cv::Rect &window ) const
  {
    return readPixels( mDataset, mPath, window );
  }

  void writeGeoTiffLike( const std::string &path, const cv::Mat &pixels, const RasterImage &like )
  {
    registerGdalDrivers();
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

  std::optional<double> exifNumber( void *gdalDataset, const char *key )
  {
    const char *value = gdalDataset ? GDALGetMetadataItem( gdalDataset, key, nullptr ) : nullptr;
    if ( !value )
      return std::nullopt;
    std::string text( value );
    for ( char &c : text )
      if ( c == '(' || c == ')' )
        c = ' ';
    char *end = nullptr;
    const double number = std::strtod( text.c_str(), &end );
    if ( end == text.c_str() || !std::isfinite( number ) || !( number > 0.0 ) )
      return std::nullopt;
    return number;
  }

  int exifOrientationTag( void *gdalDataset )
  {
    const std::optional<double> tag = exifNumber( gdalDataset, "EXIF_Orientation" );
    return tag && *tag <= 8.0 && *tag == std::floor( *tag ) ? static_cast<int>( *tag ) : 1;
  }

  std::string pixelSpaceSource( const std::string &path, const std::string &memoryPath, int *exifOrientation, bool mirrorAsTagged )
  {
    if ( memoryPath.rfind( "/vsimem/", 0 ) != 0 )
      throw std::invalid_argument( "pixelSpaceSource writes to a /vsimem/ path, not " + memoryPath );
    if ( exifOrientation )
      *exifOrientation = 1;
    registerGdalDrivers();
    CPLPushErrorHandler( CPLQuietErrorHandler );
    std::unique_ptr<void, DatasetCloser> source( GDALOpenEx( path.c_str(), GDAL_OF_RASTER | GDAL_OF_READONLY, nullptr, nullptr, nullptr ) );
    CPLPopErrorHandler();
    if ( !source )
      return path;
    const int tag = exifOrientationTag( source.get() );
    if ( exifOrientation )
      *exifOrientation = tag;
    const bool mirrored = mirrorAsTagged && viewForExifOrientation( tag ).mirrored;
    // a photo has 1-4 bands; anything else the viewer refuses with its own message, and a VRT of it would
    // describe every band (tens of thousands in a damaged file)
    const int bands = GDALGetRasterCount( source.get() );
    if ( bands < 1 || bands > 4 )
      return path;
    std::array<double, 6> gt {};
    const bool georeferenced = GDALGetGeoTransform( source.get(), gt.data() ) == CE_None || GDALGetGCPCount( source.get() ) > 0 ||
                               GDALGetMetadata( source.get(), "RPC" ) != nullptr;
    if ( !georeferenced && !mirrored )
      return path;
    {
      std::unique_ptr<void, DatasetCloser> view( GDALCreateCopy( GDALGetDriverByName( "VRT" ), memoryPath.c_str(), source.get(), FALSE, nullptr, nullptr, nullptr ) );
      if ( !view )
        return path;
      // (a viewer draws a negative pixel width mirrored: QGIS resamples it pixel for pixel)
      std::array<double, 6> pixels { 0.0, mirrored ? -1.0 : 1.0, 0.0, 0.0, 0.0, -1.0 };
      GDALSetGeoTransform( view.get(), pixels.data() );
      GDALSetProjection( view.get(), "" );
      GDALSetGCPs( view.get(), 0, nullptr, "" );
      GDALSetMetadata( view.get(), nullptr, "RPC" );
    } // closing the VRT writes it
    return memoryPath;
  }

} // namespace geostation
