// Add Photo (issue 18, item 1): a photo joins a block, or starts one, with
// its camera from the file's EXIF (written by GDAL's JPEG driver, as a
// camera writes it) or a normal-lens default, or a film camera's
// calibration; the block saved reloads with the photo unoriented.
#include <gtest/gtest.h>

#include <cmath>
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
  // the views turn and mirror it as tagged (the tag read as the view opens the file)
  const auto tagOf = []( const std::filesystem::path &file ) {
    int tag = 0;
    pixelSpaceSource( file.string(), "/vsimem/geostation-test/tag.vrt", &tag );
    return tag;
  };
  EXPECT_EQ( tagOf( mDir / "photos/portrait.jpg" ), 6 );
  // (mirrored, clockwise turn) for tags 1-8: the EXIF rows and columns, e.g. 5 (the stored rows are the
  // columns seen from the left, the stored columns the rows seen from the top) is a transpose: a mirror, then
  // a quarter turn anticlockwise
  const std::vector<std::pair<bool, int>> expected { { false, 0 }, { true, 0 }, { false, 180 }, { true, 180 },
    { true, 270 }, { false, 90 }, { true, 90 }, { false, 270 } };
  for ( int tag = 1; tag <= 8; ++tag )
  {
    const ExifView view = viewForExifOrientation( tag );
    EXPECT_EQ( std::make_pair( view.mirrored, view.turnDeg ), expected[tag - 1] ) << tag;
    // the stored pixel (c, r) of a W x H photo appears where the tag's rows and columns put it
    const auto shown = [&]( double c, double r ) {
      const double x = view.mirrored ? -c : c; // y down the view: r
      const double t = view.turnDeg * M_PI / 180.0;
      return Eigen::Vector2d( x * std::cos( t ) - r * std::sin( t ), x * std::sin( t ) + r * std::cos( t ) );
    };
    // the stored first row's direction and the first column's, in the view (x right, y down)
    const Eigen::Vector2d rowAlong = shown( 1, 0 ) - shown( 0, 0 ), columnDown = shown( 0, 1 ) - shown( 0, 0 );
    static const Eigen::Vector2d right( 1, 0 ), left( -1, 0 ), down( 0, 1 ), up( 0, -1 );
    const std::vector<std::pair<Eigen::Vector2d, Eigen::Vector2d>> exif { { right, down }, { left, down }, { left, up }, { right, up },
      { down, right }, { down, left }, { up, left }, { up, right } };
    EXPECT_LT( ( rowAlong - exif[tag - 1].first ).norm(), 1e-9 ) << tag;
    EXPECT_LT( ( columnDown - exif[tag - 1].second ).norm(), 1e-9 ) << tag;
  }
  EXPECT_EQ( std::make_pair( viewForExifOrientation( 0 ).mirrored, viewForExifOrientation( 0 ).turnDeg ), std::make_pair( false, 0 ) );
  EXPECT_EQ( viewForExifOrientation( 9 ).turnDeg, 0 );
  writeJpeg( mDir / "photos/mirrored.jpg", 640, 480, { { "EXIF_Orientation", "2" } } );
  EXPECT_NE( cameraFromPhotoFile( mDir / "photos/mirrored.jpg", "cam" ).orientationNote().find( "shown mirrored left to right (EXIF orientation 2); its views show it so" ),
             std::string::npos );
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
