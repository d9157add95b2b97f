// The block file (docs/conventions.md §5): load, validation messages with JSON paths,
// unknown keys kept, atomic save, image file checks.
#include <fstream>

#include <gdal.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "io/block.h"

using namespace geostation;
using json = nlohmann::json;

namespace
{
  const std::filesystem::path kSample = std::filesystem::path( GEOSTATION_SOURCE_DIR ) / "docs/examples/sample.geostation.json";

  json sampleJson()
  {
    std::ifstream in( kSample );
    return json::parse( in );
  }

  //! Expects loading `doc` to fail at `path` with a message containing `words`.
  void expectError( const json &doc, const std::string &path, const std::string &words )
  {
    try
    {
      Block::fromJsonText( doc.dump(), "/data/run17.geostation.json" );
      ADD_FAILURE() << "accepted a bad block; expected an error at " << path;
    }
    catch ( const BlockFormatError &e )
    {
      EXPECT_EQ( e.jsonPath(), path ) << e.what();
      EXPECT_NE( std::string( e.what() ).find( words ), std::string::npos ) << e.what();
      EXPECT_EQ( e.file(), "/data/run17.geostation.json" );
      EXPECT_EQ( std::string( e.what() ).rfind( "/data/run17.geostation.json: ", 0 ), 0u ) << e.what();
    }
  }

  struct TempDir
  {
    std::filesystem::path path;
    TempDir()
    {
      path = std::filesystem::temp_directory_path() / ( "geostation-test-" + std::to_string( ::getpid() ) + "-" + std::to_string( counter()++ ) );
      std::filesystem::create_directories( path );
    }
    ~TempDir() { std::filesystem::remove_all( path ); }
    static int &counter()
    {
      static int c = 0;
      return c;
    }
  };

  void writeTiff( const std::filesystem::path &file, int width, int height )
  {
    GDALAllRegister();
    std::filesystem::create_directories( file.parent_path() );
    GDALDriverH driver = GDALGetDriverByName( "GTiff" );
    GDALDatasetH ds = GDALCreate( driver, file.string().c_str(), width, height, 1, GDT_Byte, nullptr );
    ASSERT_NE( ds, nullptr );
    GDALClose( ds );
  }
} // namespace

TEST( Block, LoadsTheSample )
{
  const Block b = Block::load( kSample );
  EXPECT_EQ( b.crs, "EPSG:32617" );
  ASSERT_EQ( b.cameras.size(), 3u );
  const Camera &left = b.camera( "left" );
  EXPECT_EQ( left.width, 640 );
  EXPECT_DOUBLE_EQ( left.f, 812.4 );
  EXPECT_DOUBLE_EQ( left.cx, 320.5 );
  EXPECT_EQ( left.distortion.model, DistortionModel::OpenCV );
  EXPECT_DOUBLE_EQ( left.distortion.k1(), -0.21 );
  EXPECT_EQ( b.camera( "right" ).distortion.model, DistortionModel::BrownPhoto );
  EXPECT_DOUBLE_EQ( b.camera( "right" ).aspect, 1.0 ); // default
  EXPECT_EQ( b.camera( "nadir" ).distortion.model, DistortionModel::None );
  ASSERT_EQ( b.stations.size(), 2u );
  EXPECT_EQ( b.stations[0].trajectory, "P-line 17" );
  const BlockImage &image = b.image( "S0001_L" );
  ASSERT_TRUE( image.exterior.has_value() );
  EXPECT_DOUBLE_EQ( image.exterior->projectionCentre.y(), 4400321.7 );
  EXPECT_DOUBLE_EQ( image.exterior->kappaDeg, 179.8 );
  ASSERT_TRUE( image.exterior->sigma.has_value() );
  EXPECT_DOUBLE_EQ( image.exterior->sigma->kappaDeg, 0.05 );
  EXPECT_FALSE( b.image( "S0001_R" ).exterior->sigma.has_value() );
  EXPECT_FALSE( b.image( "S0002_L" ).exterior.has_value() );
  EXPECT_EQ( b.imageFilePath( image ), kSample.parent_path() / "images/S0001_L.tif" );
  ASSERT_EQ( b.camera( "nadir" ).fiducials.size(), 4u );
  EXPECT_EQ( b.camera( "nadir" ).fiducials[2].photoMm, Eigen::Vector2d( 106.0, -106.0 ) );
  ASSERT_TRUE( b.image( "S0002_L" ).innerOrientation.has_value() );
  EXPECT_DOUBLE_EQ( b.image( "S0002_L" ).innerOrientation->photoFromPixel( 1, 2 ), 115.0 );
  EXPECT_DOUBLE_EQ( b.image( "S0002_L" ).innerOrientation->sigma0Mm, 0.002 );
  EXPECT_FALSE( b.image( "S0001_L" ).innerOrientation.has_value() );
}

TEST( Block, UnknownKeysSurviveASaveAtEveryLevel )
{
  TempDir dir;
  Block b = Block::load( kSample );
  b.images[0].exterior->omegaDeg = 91.0; // an edit
  const std::filesystem::path out = dir.path / "edited.geostation.json";
  b.save( out );
  std::ifstream in( out );
  const json saved = json::parse( in );
  EXPECT_EQ( saved["project_note"], "kept on save" );
  EXPECT_EQ( saved["cameras"][0]["serial"], "CAM-0042" );
  EXPECT_EQ( saved["cameras"][0]["distortion"]["calibrated"], "2025-04-02" );
  EXPECT_DOUBLE_EQ( saved["cameras"][0]["distortion"]["k1"].get<double>(), -0.21 );
  EXPECT_DOUBLE_EQ( saved["stations"][0]["odometer_m"].get<double>(), 1520.4 );
  EXPECT_DOUBLE_EQ( saved["images"][0]["exposure_ms"].get<double>(), 2.5 );
  EXPECT_DOUBLE_EQ( saved["images"][0]["omega"].get<double>(), 91.0 );
  EXPECT_FALSE( saved["images"][2].contains( "X" ) );
  EXPECT_FALSE( std::filesystem::exists( dir.path / "edited.geostation.json.tmp-write" ) );

  // Loading the saved file gives the same block; only the image paths differ,
  // rebased onto the new folder (see SavingElsewhere...).
  json first = json::parse( b.toJsonText() ), second = json::parse( Block::load( out ).toJsonText() );
  for ( json *doc : { &first, &second } )
    for ( json &image : ( *doc )["images"] )
      image.erase( "path" );
  EXPECT_EQ( first, second );
}

TEST( Block, SavingElsewhereKeepsImagePathsPointingAtTheSameFiles )
{
  TempDir dir;
  const Block b = Block::load( kSample );
  std::filesystem::create_directories( dir.path / "results/adjusted" );
  const std::filesystem::path out = dir.path / "results/adjusted/run.geostation.json";
  b.save( out );
  const Block again = Block::load( out );
  for ( size_t i = 0; i < b.images.size(); ++i )
    EXPECT_EQ( std::filesystem::weakly_canonical( again.imageFilePath( again.images[i] ) ), std::filesystem::weakly_canonical( b.imageFilePath( b.images[i] ) ) );
  // Saved beside the original, paths stay as written.
  const Block copy = Block::fromJsonText( b.toJsonText(), kSample.parent_path() / "copy.geostation.json" );
  EXPECT_EQ( copy.images[0].path, "images/S0001_L.tif" );
}

TEST( Block, SaveIntoAMissingFolderFailsAndWritesNothing )
{
  TempDir dir;
  const Block b = Block::load( kSample );
  EXPECT_THROW( b.save( dir.path / "no/such/folder/x.geostation.json" ), std::runtime_error );
  EXPECT_TRUE( std::filesystem::is_empty( dir.path ) );
}

TEST( Block, MissingFileAndBadJsonNameTheFile )
{
  try
  {
    Block::load( "/nonexistent/run.geostation.json" );
    FAIL();
  }
  catch ( const BlockFormatError &e )
  {
    EXPECT_NE( std::string( e.what() ).find( "/nonexistent/run.geostation.json" ), std::string::npos );
    EXPECT_NE( std::string( e.what() ).find( "does not exist" ), std::string::npos );
  }
  try
  {
    Block::fromJsonText( "{\n  \"format\": \"geostation-block\",\n  \"version\": 1,,\n}", "bad.geostation.json" );
    FAIL();
  }
  catch ( const BlockFormatError &e )
  {
    EXPECT_NE( std::string( e.what() ).find( "not valid JSON (line 3" ), std::string::npos ) << e.what();
  }
}

TEST( Block, ErrorsNameTheJsonPathAndWhatWasExpected )
{
  json doc = sampleJson();
  doc["format"] = "something-else";
  expectError( doc, "$.format", "expected \"geostation-block\"" );

  doc = sampleJson();
  doc["version"] = 2;
  expectError( doc, "$.version", "reads block version 1" );

  doc = sampleJson();
  doc["crs"] = "EPSG:4326";
  expectError( doc, "$.crs", "geographic" );

  doc = sampleJson();
  doc.erase( "cameras" );
  expectError( doc, "$", "\"cameras\" is missing" );

  doc = sampleJson();
  doc["cameras"] = json::array();
  expectError( doc, "$.cameras", "at least one" );

  doc = sampleJson();
  doc["cameras"][1]["width"] = 640.5;
  expectError( doc, "$.cameras[1].width", "positive whole number" );

  doc = sampleJson();
  doc["cameras"][0]["f"] = "812";
  expectError( doc, "$.cameras[0].f", "expected a positive number (principal distance in pixels), found the string \"812\"" );

  doc = sampleJson();
  doc["cameras"][0]["distortion"]["model"] = "fisheye";
  expectError( doc, "$.cameras[0].distortion.model", "\"brown_photo\"" );

  doc = sampleJson();
  doc["cameras"][1].erase( "pixel_size_mm" );
  expectError( doc, "$.cameras[1]", "pixel_size_mm" );

  doc = sampleJson();
  doc["cameras"][2]["id"] = "left";
  expectError( doc, "$.cameras[2].id", "used twice" );

  doc = sampleJson();
  doc["stations"][1]["time"] = "yesterday";
  expectError( doc, "$.stations[1].time", "ISO 8601" );

  doc = sampleJson();
  doc["images"][1]["camera"] = "rear";
  expectError( doc, "$.images[1].camera", "camera \"rear\" is not defined in $.cameras (defined: left, right, nadir)" );

  doc = sampleJson();
  doc["images"][1]["station"] = "S9999";
  expectError( doc, "$.images[1].station", "station \"S9999\" is not defined" );

  doc = sampleJson();
  doc["images"][0].erase( "kappa" );
  expectError( doc, "$.images[0]", "missing: kappa" );

  doc = sampleJson();
  doc["images"][0]["omega"] = nullptr;
  expectError( doc, "$.images[0].omega", "expected a number (omega in degrees), found null" );

  doc = sampleJson();
  doc["images"][0]["sigma"]["Z"] = -0.1;
  expectError( doc, "$.images[0].sigma.Z", "non-negative" );

  doc = sampleJson();
  doc["images"][2]["sigma"] = doc["images"][0]["sigma"];
  expectError( doc, "$.images[2].sigma", "no exterior orientation" );

  doc = sampleJson();
  doc["cameras"][2]["fiducials"][1]["id"] = "1";
  expectError( doc, "$.cameras[2].fiducials[1].id", "used twice" );

  doc = sampleJson();
  doc["cameras"][2]["fiducials"][0].erase( "y_mm" );
  expectError( doc, "$.cameras[2].fiducials[0]", "\"y_mm\" is missing" );

  doc = sampleJson();
  doc["images"][2]["inner_orientation"]["photo_from_pixel"][1] = json::array( { 1.0, 2.0 } );
  expectError( doc, "$.images[2].inner_orientation.photo_from_pixel[1]", "three numbers" );

  doc = sampleJson();
  doc["images"][2]["id"] = "S0001_L";
  expectError( doc, "$.images[2].id", "used twice" );

  expectError( json::array(), "$", "expected an object, found an array" );
}

TEST( Block, LookupsNameWhatExists )
{
  const Block b = Block::load( kSample );
  try
  {
    b.image( "S0003_L" );
    FAIL();
  }
  catch ( const std::invalid_argument &e )
  {
    EXPECT_NE( std::string( e.what() ).find( "S0001_L, S0001_R, S0002_L" ), std::string::npos ) << e.what();
  }
  EXPECT_THROW( b.camera( "rear" ), std::invalid_argument );
  EXPECT_THROW( b.requireExterior( b.image( "S0002_L" ) ), std::invalid_argument );
  EXPECT_NO_THROW( b.requireExterior( b.image( "S0001_L" ) ) );
}

TEST( Block, ImageFileChecks )
{
  TempDir dir;
  json doc = sampleJson();
  const std::filesystem::path blockFile = dir.path / "run.geostation.json";
  const Block b = Block::fromJsonText( doc.dump(), blockFile );
  const BlockImage &image = b.image( "S0001_L" );

  try
  {
    requireReadableImageFile( b, image );
    FAIL();
  }
  catch ( const std::runtime_error &e )
  {
    EXPECT_NE( std::string( e.what() ).find( "does not exist" ), std::string::npos ) << e.what();
  }

  std::filesystem::create_directories( dir.path / "images" );
  std::ofstream( dir.path / "images/S0001_L.tif" ) << "this is not a TIFF";
  try
  {
    requireReadableImageFile( b, image );
    FAIL();
  }
  catch ( const std::runtime_error &e )
  {
    EXPECT_NE( std::string( e.what() ).find( "cannot be decoded" ), std::string::npos ) << e.what();
  }

  std::filesystem::remove( dir.path / "images/S0001_L.tif" );
  writeTiff( dir.path / "images/S0001_L.tif", 320, 240 );
  try
  {
    requireReadableImageFile( b, image );
    FAIL();
  }
  catch ( const std::runtime_error &e )
  {
    EXPECT_NE( std::string( e.what() ).find( "320 x 240 pixels but camera \"left\" declares 640 x 480" ), std::string::npos ) << e.what();
  }

  std::filesystem::remove( dir.path / "images/S0001_L.tif" );
  writeTiff( dir.path / "images/S0001_L.tif", 640, 480 );
  EXPECT_NO_THROW( requireReadableImageFile( b, image ) );
}
