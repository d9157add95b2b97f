// Add Photo (issue 18, item 1): a photo joins a block, or starts one, with
// its camera from the file's EXIF (written by GDAL's JPEG driver, as a
// camera writes it) or a normal-lens default, or a film camera's
// calibration; the block saved reloads with the photo unoriented.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <unistd.h>

#include <gdal.h>

#include "io/block.h"
#include "io/photoimport.h"
#include "io/rasterfile.h"

using namespace geostation;

namespace
{
  //! A grey JPEG of the given size with EXIF items (key, value) written by GDAL.
  void writeJpeg( const std::filesystem::path &file, int width, int height, const std::vector<std::pair<std::string, std::string>> &exif )
  {
    GDALAllRegister();
    GDALDatasetH mem = GDALCreate( GDALGetDriverByName( "MEM" ), "", width, height, 1, GDT_Byte, nullptr );
    std::vector<unsigned char> pixels( static_cast<size_t>( width ) * height );
    for ( size_t i = 0; i < pixels.size(); ++i )
      pixels[i] = static_cast<unsigned char>( ( i * 7 ) % 251 );
    EXPECT_EQ( GDALRasterIO( GDALGetRasterBand( mem, 1 ), GF_Write, 0, 0, width, height, pixels.data(), width, height, GDT_Byte, 0, 0 ), CE_None );
    for ( const auto &[key, value] : exif )
      GDALSetMetadataItem( mem, key.c_str(), value.c_str(), nullptr );
    GDALDatasetH jpeg = GDALCreateCopy( GDALGetDriverByName( "JPEG" ), file.string().c_str(), mem, FALSE, nullptr, nullptr, nullptr );
    ASSERT_NE( jpeg, nullptr );
    GDALClose( jpeg );
    GDALClose( mem );
  }

  class PhotoImport : public ::testing::Test
  {
    protected:
      void SetUp() override
      {
        mDir = std::filesystem::temp_directory_path() / ( "geostation-photoimport-" + std::to_string( ::getpid() ) );
        std::filesystem::remove_all( mDir );
        std::filesystem::create_directories( mDir / "photos" );
      }
      void TearDown() override { std::filesystem::remove_all( mDir ); }
      std::filesystem::path mDir;
  };
} // namespace

TEST_F( PhotoImport, CameraFromExifOrANormalLens )
{
  // focal length 4.5 mm on a sensor of 200 px/mm (focal-plane resolution 2000 per cm): f = 900 px
  writeJpeg( mDir / "photos/plane.jpg", 640, 480, { { "EXIF_FocalLength", "(4.5)" }, { "EXIF_FocalPlaneXResolution", "(2000)" }, { "EXIF_FocalPlaneResolutionUnit", "3" },
    { "EXIF_FocalLengthIn35mmFilm", "28" } } );
  PhotoFileCamera c = cameraFromPhotoFile( mDir / "photos/plane.jpg", "cam" );
  EXPECT_EQ( c.focalSource, "exif_focal_plane_resolution" );
  EXPECT_NEAR( c.camera.f, 900.0, 1e-9 );
  EXPECT_EQ( c.camera.width, 640 );
  EXPECT_EQ( c.camera.height, 480 );
  EXPECT_NEAR( c.camera.cx, 320.0, 1e-12 );
  EXPECT_NEAR( c.camera.cy, 240.0, 1e-12 );

  // 28 mm on 35 mm film (diagonal 43.27 mm) over an 800-px diagonal
  writeJpeg( mDir / "photos/equivalent.jpg", 640, 480, { { "EXIF_FocalLengthIn35mmFilm", "28" } } );
  c = cameraFromPhotoFile( mDir / "photos/equivalent.jpg", "cam" );
  EXPECT_EQ( c.focalSource, "exif_35mm_equivalent" );
  EXPECT_NEAR( c.camera.f, 28.0 / 43.27 * 800.0, 1e-9 );

  writeJpeg( mDir / "photos/bare.jpg", 640, 480, {} );
  c = cameraFromPhotoFile( mDir / "photos/bare.jpg", "cam" );
  EXPECT_EQ( c.focalSource, "normal_lens_default" );
  EXPECT_NEAR( c.camera.f, 50.0 / 43.27 * 800.0, 1e-9 );
  EXPECT_EQ( c.exifOrientation, 1 );
  EXPECT_EQ( c.orientationNote(), "" );

  // a phone photo tagged "turn 90 degrees clockwise to show": measured as stored, and the operator told so
  writeJpeg( mDir / "photos/portrait.jpg", 640, 480, { { "EXIF_Orientation", "6" } } );
  c = cameraFromPhotoFile( mDir / "photos/portrait.jpg", "cam" );
  EXPECT_EQ( c.exifOrientation, 6 );
  EXPECT_EQ( c.camera.width, 640 ); // the stored pixels' camera
  EXPECT_NE( c.orientationNote().find( "tagged to be shown turned 90 degrees clockwise (EXIF orientation 6); its views show it so, but its pixels are measured as stored" ),
             std::string::npos ) << c.orientationNote();
  // the views turn it as tagged (the tag read as the view opens the file); a mirrored one they show as stored
  const auto tagOf = []( const std::filesystem::path &file ) {
    int tag = 0;
    pixelSpaceSource( file.string(), "/vsimem/geostation-test/tag.vrt", &tag );
    return tag;
  };
  EXPECT_EQ( tagOf( mDir / "photos/portrait.jpg" ), 6 );
  EXPECT_EQ( viewTurnForExifOrientation( 6 ), 90 );
  EXPECT_EQ( viewTurnForExifOrientation( 3 ), 180 );
  EXPECT_EQ( viewTurnForExifOrientation( 8 ), 270 );
  EXPECT_EQ( viewTurnForExifOrientation( 1 ), 0 );
  EXPECT_EQ( viewTurnForExifOrientation( 0 ), 0 );
  for ( const int mirrored : { 2, 4, 5, 7 } )
    EXPECT_FALSE( viewTurnForExifOrientation( mirrored ) ) << mirrored;
  writeJpeg( mDir / "photos/mirrored.jpg", 640, 480, { { "EXIF_Orientation", "2" } } );
  EXPECT_NE( cameraFromPhotoFile( mDir / "photos/mirrored.jpg", "cam" ).orientationNote().find( "appears unmirrored in the views" ), std::string::npos );
  EXPECT_EQ( tagOf( mDir / "photos/bare.jpg" ), 1 );
  writeJpeg( mDir / "photos/odd.jpg", 64, 48, { { "EXIF_Orientation", "9" } } );
  EXPECT_EQ( tagOf( mDir / "photos/odd.jpg" ), 1 );

  std::ofstream( mDir / "photos/broken.jpg" ) << "not a photo";
  EXPECT_THROW( cameraFromPhotoFile( mDir / "photos/broken.jpg", "cam" ), std::runtime_error );
  EXPECT_THROW( cameraFromPhotoFile( mDir / "photos/missing.jpg", "cam" ), std::runtime_error );
  EXPECT_EQ( tagOf( mDir / "photos/broken.jpg" ), 1 );
  EXPECT_EQ( tagOf( mDir / "photos/missing.jpg" ), 1 );
}

TEST_F( PhotoImport, PhotosJoinANewBlockThatReloads )
{
  writeJpeg( mDir / "photos/site.jpg", 640, 480, {} );
  writeJpeg( mDir / "photos/other.jpg", 320, 240, {} );
  const std::filesystem::path blockFile = mDir / "site.geostation.json";
  Block block = newPhotoBlock( "EPSG:25832", blockFile );
  const Camera film = cameraFromJsonText( R"({"id": "rmk", "width": 640, "height": 480, "f": 1200.5, "cx": 320.2, "cy": 239.7, "pixel_size_mm": 0.1275,
      "fiducials": [{"id": "F1", "x_mm": -40, "y_mm": 30}, {"id": "F2", "x_mm": 40, "y_mm": 30}, {"id": "F3", "x_mm": 40, "y_mm": -30}, {"id": "F4", "x_mm": -40, "y_mm": -30}]})" );
  EXPECT_EQ( film.fiducials.size(), 4u );
  EXPECT_EQ( addPhotoToBlock( block, mDir / "photos/site.jpg", film ), "site" );
  // the same photo again: a new id; the camera is the block's
  EXPECT_EQ( addPhotoToBlock( block, mDir / "photos/site.jpg", film ), "site_2" );
  EXPECT_EQ( block.cameras.size(), 1u );
  // a photo of another size cannot use that camera
  EXPECT_THROW( addPhotoToBlock( block, mDir / "photos/other.jpg", film ), std::runtime_error );
  EXPECT_EQ( block.images.size(), 2u );
  EXPECT_EQ( addPhotoToBlock( block, mDir / "photos/other.jpg", cameraFromPhotoFile( mDir / "photos/other.jpg", "phone" ).camera ), "other" );
  block.save( blockFile );

  const Block reloaded = Block::load( blockFile );
  ASSERT_EQ( reloaded.images.size(), 3u );
  EXPECT_EQ( reloaded.images[0].path, "photos/site.jpg" );
  EXPECT_FALSE( reloaded.images[0].exterior.has_value() );
  EXPECT_EQ( reloaded.cameraOf( reloaded.images[0] ).fiducials.size(), 4u );
  EXPECT_NEAR( *reloaded.cameraOf( reloaded.images[0] ).pixelSizeMm, 0.1275, 1e-12 );
  EXPECT_NO_THROW( requireReadableImageFile( reloaded, reloaded.images[2] ) );

  // a camera with a bad value: the block reader's sentence, naming the key
  try
  {
    cameraFromJsonText( R"({"id": "bad", "width": 640, "height": 480, "f": -3, "cx": 320, "cy": 240})" );
    FAIL() << "a negative f was accepted";
  }
  catch ( const BlockFormatError &e )
  {
    EXPECT_NE( std::string( e.what() ).find( "f" ), std::string::npos ) << e.what();
  }
}
