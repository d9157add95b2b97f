/***************************************************************************
  testrasterfile.cpp - images as they come: alpha, palettes, 16 bits, EXIF
 ***************************************************************************/
#include <fstream>

#include <gtest/gtest.h>

#include <gdal.h>
#include <gdal_priv.h>

#include "io/rasterfile.h"
#include "testfiles.h"

using namespace geostation;
using geostation::testing::errorOf;
using geostation::testing::freshTestFolder;
namespace fs = std::filesystem;

namespace
{
  const int kWidth = 40, kHeight = 20; // not square: a rotation would show

  //! Band b (0-based) of pixel (col, row): a different value everywhere.
  int value( int b, int col, int row ) { return ( 50 * b + 3 * col + 5 * row ) % 256; }

  /**
   * Writes `bands` 8-bit bands (or 16-bit: values times 257) through the
   * driver, with the given colour interpretations and creation options.
   */
  void writeRaster( const fs::path &file, const char *driver, const std::vector<GDALColorInterp> &interp, GDALDataType type = GDT_Byte,
                    const std::vector<std::string> &options = {}, const std::map<std::string, std::string> &metadata = {} )
  {
    GDALAllRegister();
    const int bands = static_cast<int>( interp.size() );
    GDALDataset *mem = GetGDALDriverManager()->GetDriverByName( "MEM" )->Create( "", kWidth, kHeight, bands, type, nullptr );
    for ( int b = 0; b < bands; ++b )
    {
      std::vector<unsigned short> row( kWidth );
      for ( int r = 0; r < kHeight; ++r )
      {
        for ( int c = 0; c < kWidth; ++c )
          row[c] = static_cast<unsigned short>( value( b, c, r ) * ( type == GDT_UInt16 ? 257 : 1 ) );
        ASSERT_EQ( mem->GetRasterBand( b + 1 )->RasterIO( GF_Write, 0, r, kWidth, 1, row.data(), kWidth, 1, GDT_UInt16, 0, 0 ), CE_None );
      }
      mem->GetRasterBand( b + 1 )->SetColorInterpretation( interp[b] );
    }
    for ( const auto &item : metadata )
      mem->SetMetadataItem( item.first.c_str(), item.second.c_str() );
    std::vector<const char *> creation;
    for ( const std::string &o : options )
      creation.push_back( o.c_str() );
    creation.push_back( nullptr );
    GDALDataset *out = GetGDALDriverManager()->GetDriverByName( driver )->CreateCopy( file.c_str(), mem, FALSE, const_cast<char **>( creation.data() ), nullptr, nullptr );
    ASSERT_NE( out, nullptr );
    GDALClose( out );
    GDALClose( mem );
  }
} // namespace

TEST( RasterFile, AlphaBandsAreLeftOut )
{
  const fs::path dir = freshTestFolder( "raster-alpha" );
  writeRaster( dir / "rgba.png", "PNG", { GCI_RedBand, GCI_GreenBand, GCI_BlueBand, GCI_AlphaBand } );
  const RasterImage rgba = readRaster( ( dir / "rgba.png" ).string() );
  ASSERT_EQ( rgba.pixels.type(), CV_8UC3 );
  ASSERT_EQ( rgba.pixels.cols, kWidth );
  for ( const auto &p : { cv::Point( 0, 0 ), cv::Point( 39, 19 ), cv::Point( 17, 3 ) } )
    EXPECT_EQ( rgba.pixels.at<cv::Vec3b>( p ), cv::Vec3b( value( 0, p.x, p.y ), value( 1, p.x, p.y ), value( 2, p.x, p.y ) ) ) << p;

  writeRaster( dir / "greyalpha.tif", "GTiff", { GCI_GrayIndex, GCI_AlphaBand }, GDT_UInt16, { "ALPHA=YES" } );
  const RasterImage greyAlpha = readRaster( ( dir / "greyalpha.tif" ).string() );
  ASSERT_EQ( greyAlpha.pixels.type(), CV_16UC1 );
  EXPECT_EQ( greyAlpha.pixels.at<ushort>( 7, 11 ), value( 0, 11, 7 ) * 257 );

  // four bands that are not RGB + alpha (e.g. RGB + near infrared): refused with the layout named
  writeRaster( dir / "rgbn.tif", "GTiff", { GCI_RedBand, GCI_GreenBand, GCI_BlueBand, GCI_Undefined }, GDT_Byte, { "PHOTOMETRIC=RGB", "ALPHA=NO" } );
  const std::string error = errorOf( [&] { readRaster( ( dir / "rgbn.tif" ).string() ); } );
  EXPECT_NE( error.find( "has 4 bands (Red, Green, Blue, Undefined); grey, RGB, and either with an alpha band are supported" ), std::string::npos ) << error;
  fs::remove_all( dir );
}

TEST( RasterFile, PaletteImagesBecomeTheirColours )
{
  const fs::path dir = freshTestFolder( "raster-palette" );
  for ( const bool grey : { false, true } )
  {
    GDALAllRegister();
    GDALDataset *mem = GetGDALDriverManager()->GetDriverByName( "MEM" )->Create( "", kWidth, kHeight, 1, GDT_Byte, nullptr );
    GDALColorTable table;
    for ( int i = 0; i < 4; ++i )
    {
      const GDALColorEntry e { static_cast<short>( 60 * i ), static_cast<short>( grey ? 60 * i : 255 - 60 * i ), static_cast<short>( grey ? 60 * i : 10 * i ), 255 };
      table.SetColorEntry( i, &e );
    }
    mem->GetRasterBand( 1 )->SetColorTable( &table );
    std::vector<unsigned char> indices( kWidth * kHeight );
    for ( int i = 0; i < kWidth * kHeight; ++i )
      indices[i] = static_cast<unsigned char>( i % 5 ); // 4 is beyond the table
    ASSERT_EQ( mem->GetRasterBand( 1 )->RasterIO( GF_Write, 0, 0, kWidth, kHeight, indices.data(), kWidth, kHeight, GDT_Byte, 0, 0 ), CE_None );
    const fs::path file = dir / ( grey ? "grey.png" : "colour.png" );
    GDALClose( GetGDALDriverManager()->GetDriverByName( "PNG" )->CreateCopy( file.c_str(), mem, FALSE, nullptr, nullptr, nullptr ) );
    GDALClose( mem );

    const RasterImage image = readRaster( file.string() );
    ASSERT_EQ( image.pixels.type(), grey ? CV_8UC1 : CV_8UC3 );
    // pixel 2 has index 2, pixel 4 index 4 (beyond the table: black)
    if ( grey )
    {
      EXPECT_EQ( image.pixels.at<uchar>( 0, 2 ), 120 );
      EXPECT_EQ( image.pixels.at<uchar>( 0, 4 ), 0 );
    }
    else
    {
      EXPECT_EQ( image.pixels.at<cv::Vec3b>( 0, 2 ), cv::Vec3b( 120, 135, 20 ) );
      EXPECT_EQ( image.pixels.at<cv::Vec3b>( 0, 4 ), cv::Vec3b( 0, 0, 0 ) );
    }
  }
  fs::remove_all( dir );
}

TEST( RasterFile, SixteenBitsAndExifOrientationAsStored )
{
  const fs::path dir = freshTestFolder( "raster-exif" );
  writeRaster( dir / "deep.tif", "GTiff", { GCI_RedBand, GCI_GreenBand, GCI_BlueBand }, GDT_UInt16 );
  const RasterImage deep = readRaster( ( dir / "deep.tif" ).string() );
  ASSERT_EQ( deep.pixels.type(), CV_16UC3 );
  EXPECT_EQ( deep.pixels.at<cv::Vec3w>( 19, 39 ), cv::Vec3w( value( 0, 39, 19 ) * 257, value( 1, 39, 19 ) * 257, value( 2, 39, 19 ) * 257 ) );

  // a JPEG tagged "rotate 90 degrees clockwise to display" (EXIF orientation 6): read as stored
  writeRaster( dir / "rotated.jpg", "JPEG", { GCI_GrayIndex }, GDT_Byte, { "QUALITY=100" }, { { "EXIF_Orientation", "6" } } );
  GDALDatasetH written = GDALOpen( ( dir / "rotated.jpg" ).c_str(), GA_ReadOnly );
  ASSERT_NE( written, nullptr );
  const char *orientation = GDALGetMetadataItem( written, "EXIF_Orientation", nullptr );
  ASSERT_NE( orientation, nullptr ); // the tag is really in the file
  EXPECT_STREQ( orientation, "6" );
  GDALClose( written );
  const RasterImage rotated = readRaster( ( dir / "rotated.jpg" ).string() );
  ASSERT_EQ( rotated.pixels.cols, kWidth );
  ASSERT_EQ( rotated.pixels.rows, kHeight );
  EXPECT_NEAR( rotated.pixels.at<uchar>( 3, 30 ), value( 0, 30, 3 ), 3 ); // not rotated: (col 30, row 3) as written
  fs::remove_all( dir );
}

TEST( RasterFile, AReaderKeptOpenReadsWindowsLikeReadRasterWindow )
{
  const fs::path dir = freshTestFolder( "rasterreader" );
  writeRaster( dir / "rgb.tif", "GTiff", { GCI_RedBand, GCI_GreenBand, GCI_BlueBand } );
  writeRaster( dir / "deep.tif", "GTiff", { GCI_GrayIndex }, GDT_UInt16 );
  const RasterReader rgb( ( dir / "rgb.tif" ).string() ), deep( ( dir / "deep.tif" ).string() );
  EXPECT_EQ( rgb.size(), cv::Size( kWidth, kHeight ) );
  EXPECT_TRUE( rgb.eightBit() );
  EXPECT_FALSE( deep.eightBit() );
  for ( const cv::Rect &window : { cv::Rect( 0, 0, kWidth, kHeight ), cv::Rect( 7, 3, 11, 9 ), cv::Rect( kWidth - 1, kHeight - 1, 1, 1 ) } )
  {
    const cv::Mat a = rgb.read( window ).pixels, b = readRasterWindow( ( dir / "rgb.tif" ).string(), window ).pixels;
    ASSERT_EQ( a.size(), window.size() );
    EXPECT_EQ( cv::norm( a, b, cv::NORM_INF ), 0.0 );
    EXPECT_EQ( a.at<cv::Vec3b>( window.height - 1, window.width - 1 )[2], value( 2, window.br().x - 1, window.br().y - 1 ) );
  }
  EXPECT_EQ( deep.read( cv::Rect( 5, 5, 2, 2 ) ).pixels.at<uint16_t>( 1, 1 ), value( 0, 6, 6 ) * 257 );
  const std::string outside = errorOf( [&] { rgb.read( cv::Rect( kWidth - 2, 0, 5, 5 ) ); } );
  EXPECT_NE( outside.find( "does not lie in the raster" ), std::string::npos ) << outside;
  const std::string missing = errorOf( [&] { RasterReader( ( dir / "missing.tif" ).string() ); } );
  EXPECT_NE( missing.find( "missing.tif" ), std::string::npos ) << missing;
}

TEST( RasterFile, AGeoreferencedImageIsShownInItsPixels )
{
  // a scanned photo archived with a world file, and a GeoTIFF: a viewer placing rasters by their georeferencing
  // is given a VRT of the same pixels in pixel space (x = col, y = -row, no CRS); a plain image is given as it is
  const fs::path dir = freshTestFolder( "pixelspace" );
  writeRaster( dir / "scan.jpg", "JPEG", { GCI_GrayIndex } );
  {
    std::ofstream world( dir / "scan.wld" );
    world << "0.5\n0\n0\n-0.5\n500000.25\n5200000.25\n";
  }
  const RasterImage plainRead = readRaster( ( dir / "scan.jpg" ).string() );
  ASSERT_TRUE( plainRead.geoTransform ) << "GDAL reads the world file";
  const std::string view = pixelSpaceSource( ( dir / "scan.jpg" ).string(), "/vsimem/geostation-test/scan-pixels.vrt" );
  ASSERT_EQ( view, "/vsimem/geostation-test/scan-pixels.vrt" );
  GDALDatasetH ds = GDALOpen( view.c_str(), GA_ReadOnly );
  ASSERT_NE( ds, nullptr );
  double gt[6] = {};
  ASSERT_EQ( GDALGetGeoTransform( ds, gt ), CE_None );
  EXPECT_EQ( std::vector<double>( gt, gt + 6 ), std::vector<double>( { 0.0, 1.0, 0.0, 0.0, 0.0, -1.0 } ) );
  EXPECT_STREQ( GDALGetProjectionRef( ds ), "" );
  EXPECT_EQ( GDALGetGCPCount( ds ), 0 );
  std::vector<unsigned char> pixels( kWidth * kHeight );
  ASSERT_EQ( GDALRasterIO( GDALGetRasterBand( ds, 1 ), GF_Read, 0, 0, kWidth, kHeight, pixels.data(), kWidth, kHeight, GDT_Byte, 0, 0 ), CE_None );
  ASSERT_EQ( plainRead.pixels.size(), cv::Size( kWidth, kHeight ) );
  ASSERT_EQ( plainRead.pixels.type(), CV_8UC1 );
  EXPECT_EQ( cv::countNonZero( cv::Mat( kHeight, kWidth, CV_8UC1, pixels.data() ) != plainRead.pixels ), 0 ) << "the same pixels";
  GDALClose( ds );
  discardMemoryRaster( view );

  // a GeoTIFF with a CRS: the same
  RasterImage like;
  like.geoTransform = std::array<double, 6> { 400000.0, 0.2, 0.0, 5100000.0, 0.0, -0.2 };
  writeGeoTiffLike( ( dir / "ortho.tif" ).string(), plainRead.pixels, like );
  EXPECT_EQ( pixelSpaceSource( ( dir / "ortho.tif" ).string(), "/vsimem/geostation-test/ortho.vrt" ), "/vsimem/geostation-test/ortho.vrt" );
  discardMemoryRaster( "/vsimem/geostation-test/ortho.vrt" );
  // a plain image, and one that cannot be opened: as they are (the viewer says why)
  writeRaster( dir / "plain.png", "PNG", { GCI_GrayIndex } );
  EXPECT_EQ( pixelSpaceSource( ( dir / "plain.png" ).string(), "/vsimem/geostation-test/plain.vrt" ), ( dir / "plain.png" ).string() );
  EXPECT_EQ( pixelSpaceSource( ( dir / "missing.tif" ).string(), "/vsimem/geostation-test/missing.vrt" ), ( dir / "missing.tif" ).string() );
  EXPECT_THROW( pixelSpaceSource( ( dir / "plain.png" ).string(), ( dir / "view.vrt" ).string() ), std::invalid_argument );
  // a photo tagged to be shown mirrored, for a viewer that mirrors it: a VRT at x = -col
  {
    GDALDatasetH memory = GDALCreate( GDALGetDriverByName( "MEM" ), "", kWidth, kHeight, 1, GDT_Byte, nullptr );
    GDALSetMetadataItem( memory, "EXIF_Orientation", "5", nullptr );
    GDALClose( GDALCreateCopy( GDALGetDriverByName( "JPEG" ), ( dir / "transposed.jpg" ).string().c_str(), memory, FALSE, nullptr, nullptr, nullptr ) );
    GDALClose( memory );
  }
  int tag = 0;
  EXPECT_EQ( pixelSpaceSource( ( dir / "transposed.jpg" ).string(), "/vsimem/geostation-test/transposed.vrt", &tag ), ( dir / "transposed.jpg" ).string() );
  EXPECT_EQ( tag, 5 );
  ASSERT_EQ( pixelSpaceSource( ( dir / "transposed.jpg" ).string(), "/vsimem/geostation-test/transposed.vrt", &tag, true ), "/vsimem/geostation-test/transposed.vrt" );
  ds = GDALOpen( "/vsimem/geostation-test/transposed.vrt", GA_ReadOnly );
  ASSERT_NE( ds, nullptr );
  ASSERT_EQ( GDALGetGeoTransform( ds, gt ), CE_None );
  EXPECT_EQ( std::vector<double>( gt, gt + 6 ), std::vector<double>( { 0.0, -1.0, 0.0, 0.0, 0.0, -1.0 } ) );
  EXPECT_EQ( GDALGetRasterXSize( ds ), kWidth );
  GDALClose( ds );
  discardMemoryRaster( "/vsimem/geostation-test/transposed.vrt" );
  // not mirrored: as it is
  EXPECT_EQ( pixelSpaceSource( ( dir / "plain.png" ).string(), "/vsimem/geostation-test/plain.vrt", nullptr, true ), ( dir / "plain.png" ).string() );
  // a georeferenced raster of 5 bands is no photo: as it is (a damaged file claiming tens of thousands of bands
  // made the VRT describe each of them; fuzz regression pixel-space-vrt-of-42753-bands)
  writeRaster( dir / "bands.tif", "GTiff", { GCI_GrayIndex, GCI_Undefined, GCI_Undefined, GCI_Undefined, GCI_Undefined } );
  {
    std::ofstream world( dir / "bands.tfw" );
    world << "0.5\n0\n0\n-0.5\n500000.25\n5200000.25\n";
  }
  EXPECT_EQ( pixelSpaceSource( ( dir / "bands.tif" ).string(), "/vsimem/geostation-test/bands.vrt" ), ( dir / "bands.tif" ).string() );
}
