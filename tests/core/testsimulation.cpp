// The survey simulator: exact terrain ray casting, camera-ray lattice, the
// rendered images against the camera model (control target centroids to
// 0.01 px), the truth outputs, determinism, GNSS/INS noise and bad input.
#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>

#include <gdal.h>
#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>
#include <ogr_api.h>
#include <ogr_srs_api.h>

#include "dem/dem.h"
#include "dem/monoplotter.h"
#include "adjustment/innerorientation.h"
#include "imageproc/fiducialdetection.h"
#include "simulation/filmscan.h"
#include "geometry/projection.h"
#include "io/block.h"
#include "simulation/degradation.h"
#include "simulation/heightfield.h"
#include "simulation/renderer.h"
#include "simulation/surveyrig.h"
#include "simulation/surveysimulator.h"
#include "simulation/truthwriter.h"
#include "simulationtruth.h"
#include "syntheticterrain.h"

using namespace geostation;

namespace
{
  std::filesystem::path tempDir( const std::string &name )
  {
    const std::filesystem::path dir = std::filesystem::temp_directory_path() / ( "geostation-sim-" + name + "-" + std::to_string( ::getpid() ) );
    std::filesystem::remove_all( dir );
    return dir;
  }

  cv::Mat readRgb( const std::filesystem::path &path )
  {
    GDALDatasetH ds = GDALOpen( path.string().c_str(), GA_ReadOnly );
    if ( !ds )
      return {};
    cv::Mat rgb( GDALGetRasterYSize( ds ), GDALGetRasterXSize( ds ), CV_8UC3 );
    int bands[3] = { 1, 2, 3 };
    const CPLErr err = GDALDatasetRasterIO( ds, GF_Read, 0, 0, rgb.cols, rgb.rows, rgb.data, rgb.cols, rgb.rows, GDT_Byte, 3, bands, 3, rgb.step[0], 1 );
    GDALClose( ds );
    return err == CE_None ? rgb : cv::Mat();
  }

  //! A small aerial survey, simulated once for the tests that read outputs.
  const std::filesystem::path &aerialRun()
  {
    static std::filesystem::path dir;
    if ( dir.empty() )
    {
      dir = tempDir( "aerial" );
      SimulationOptions options;
      options.preset = SurveyPreset::AerialStereo;
      options.seed = 11;
      options.outputDir = dir;
      options.imageWidth = 768;
      options.imageHeight = 768;
      options.stations = 3;
      geostation::simulateSurvey( options );
    }
    return dir;
  }
}

TEST( HeightField, RayHitsTheBilinearSurfaceExactly )
{
  const HeightField field( 1000.0, 2000.0, 0.5, 200, 160, []( double x, double y ) { return 50.0 + 4.0 * std::sin( x / 7.0 ) * std::cos( y / 5.0 ); } );
  std::mt19937 random( 3 );
  std::uniform_real_distribution<double> ux( 1010, 1090 ), uy( 1930, 1990 ), angle( 0, 2 * M_PI ), elevation( 0.02, 1.5 );
  int hits = 0;
  for ( int k = 0; k < 2000; ++k )
  {
    const Eigen::Vector3d origin( ux( random ), uy( random ), 62.0 );
    const double a = angle( random ), e = elevation( random );
    const Eigen::Vector3d direction( std::cos( a ) * std::cos( e ), std::sin( a ) * std::cos( e ), -std::sin( e ) );
    const std::optional<TerrainHit> hit = field.intersect( origin, direction );
    // brute force: fine steps, first sign change
    std::optional<double> first;
    for ( double t = 0.0; t < 400.0; t += 0.002 )
    {
      const Eigen::Vector3d p = origin + t * direction;
      const std::optional<double> h = field.heightAt( p.x(), p.y() );
      if ( !h )
        break;
      if ( p.z() <= *h )
      {
        first = t;
        break;
      }
    }
    ASSERT_EQ( hit.has_value(), first.has_value() ) << k;
    if ( !hit )
      continue;
    ++hits;
    EXPECT_NEAR( hit->t, *first, 0.0025 ) << k;
    EXPECT_NEAR( ( origin + hit->t * direction ).z(), *field.heightAt( hit->point.x(), hit->point.y() ), 1e-6 ) << k;
  }
  EXPECT_GT( hits, 1000 );
}

TEST( HeightField, GeoTiffReadsBackThroughDemUnchanged )
{
  const HeightField field( 400000.25, 5000000.75, 0.5, 64, 48, []( double x, double y ) { return 120.0 + 0.3 * ( x - 400000 ) - 0.2 * ( y - 5000000 ); } );
  const std::string path = syntheticterrain::tempPath( "heightfield" );
  field.writeGeoTiff( path, "EPSG:32633" );
  const Dem dem( path );
  std::mt19937 random( 5 );
  std::uniform_real_distribution<double> ux( 400000.3, 400031.7 ), uy( 4999977.3, 5000000.7 );
  for ( int k = 0; k < 500; ++k )
  {
    const double x = ux( random ), y = uy( random );
    ASSERT_TRUE( dem.heightAt( x, y ).has_value() );
    EXPECT_NEAR( *dem.heightAt( x, y ), *field.heightAt( x, y ), 1e-4 );
  }
  std::filesystem::remove( path );
}

TEST( CameraRays, LatticeRaysAgreeWithTheCameraModel )
{
  Camera camera;
  camera.id = "c";
  camera.width = 640;
  camera.height = 480;
  camera.f = 512;
  camera.cx = 321.3;
  camera.cy = 239.2;
  camera.distortion.model = DistortionModel::OpenCV;
  camera.distortion.coeffs = { -0.12, 0.03, 2e-4, -1e-4, 0 };
  const CameraRays rays( camera );
  std::mt19937 random( 7 );
  std::uniform_real_distribution<double> uc( 0, 640 ), ur( 0, 480 );
  double worst = 0.0;
  for ( int k = 0; k < 5000; ++k )
  {
    const Eigen::Vector2d pixel( uc( random ), ur( random ) );
    Eigen::Vector3d ray;
    ASSERT_TRUE( rays.rayAt( pixel.x(), pixel.y(), ray ) );
    const PixelProjection back = camera.pixelFromCamera( ray );
    ASSERT_TRUE( back.ok() );
    worst = std::max( worst, ( back.pixelInImage - pixel ).norm() );
  }
  EXPECT_LT( worst, 1e-3 ) << "lattice interpolation error, px";
}

TEST( Simulation, TargetCentroidsAgreeWithTheCameraModel )
{
  // Each control target's white disc, located in the rendered image by its
  // intensity centroid, against the area centroid of the disc's outline
  // projected with the exact orientation (which includes the perspective
  // and lens shift of the centroid).
  const std::filesystem::path &dir = aerialRun();
  const Block truthBlock = Block::load( dir / "truth.geostation.json" );
  const TruthTable truth = readTruth( dir / "truth.gpkg" );
  const Dem terrain( ( dir / "terrain.tif" ).string() );
  int measured = 0, discs = 0, agreeing = 0;
  double worst = 0.0;
  for ( const BlockImage &image : truthBlock.images )
  {
    const cv::Mat rgb = readRgb( dir / image.path );
    ASSERT_FALSE( rgb.empty() );
    const OrientedImage oriented( truthBlock.cameraOf( image ), *image.exterior );
    for ( const auto &[id, centre] : truth.control )
    {
      if ( !truth.imageTruth.count( { id, image.id } ) )
        continue;
      // the disc outline on the terrain, projected; its polygon's area centroid
      const double radius = 0.4; // aerial_stereo at 0.1 m: 4 x GSD
      std::vector<Eigen::Vector2d> outline;
      for ( int k = 0; k < 720; ++k )
      {
        const double a = 2 * M_PI * k / 720;
        const double x = centre.x() + radius * std::cos( a ), y = centre.y() + radius * std::sin( a );
        outline.push_back( oriented.projectGroundToPixel( Eigen::Vector3d( x, y, *terrain.heightAt( x, y ) ) ).pixelInImage );
      }
      double area = 0.0;
      Eigen::Vector2d centroid = Eigen::Vector2d::Zero();
      for ( size_t k = 0; k < outline.size(); ++k )
      {
        const Eigen::Vector2d &p = outline[k], &q = outline[( k + 1 ) % outline.size()];
        const double cross = p.x() * q.y() - q.x() * p.y();
        area += cross;
        centroid += ( p + q ) * cross;
      }
      centroid /= 3.0 * area;
      // window: the pixels within the disc plus 1.5 px, all on the black square
      const double reach = std::sqrt( std::abs( area ) / 2 / M_PI ) + 1.5;
      const int c0 = static_cast<int>( std::floor( centroid.x() - reach ) ), r0 = static_cast<int>( std::floor( centroid.y() - reach ) );
      const int c1 = static_cast<int>( std::ceil( centroid.x() + reach ) ), r1 = static_cast<int>( std::ceil( centroid.y() + reach ) );
      if ( c0 < 0 || r0 < 0 || c1 >= rgb.cols || r1 >= rgb.rows )
        continue;
      const auto inWindow = [&]( int c, int r ) { return ( Eigen::Vector2d( c + 0.5, r + 0.5 ) - centroid ).norm() <= reach; };
      // black and white levels of this target (it may lie in shade)
      double black = 255.0, white = 0.0;
      for ( int r = r0; r <= r1; ++r )
        for ( int c = c0; c <= c1; ++c )
          if ( inWindow( c, r ) )
          {
            black = std::min<double>( black, rgb.at<cv::Vec3b>( r, c )[1] );
            white = std::max<double>( white, rgb.at<cv::Vec3b>( r, c )[1] );
          }
      double sum = 0.0;
      Eigen::Vector2d moment = Eigen::Vector2d::Zero();
      for ( int r = r0; r <= r1; ++r )
        for ( int c = c0; c <= c1; ++c )
          if ( inWindow( c, r ) )
          {
            const double w = ( rgb.at<cv::Vec3b>( r, c )[1] - black ) / ( white - black );
            sum += w;
            moment += w * Eigen::Vector2d( c + 0.5, r + 0.5 );
          }
      const Eigen::Vector2d found = moment / sum;
      // the truth's disc (image_truth's disc_px, disc_in_view, disc_in_sun): its area is the projected disc's, and
      // it calls the disc whole (in view and in sunlight) where the rendering shows all of it white
      const auto disc = truth.targetDiscs.find( { id, image.id } );
      ASSERT_NE( disc, truth.targetDiscs.end() ) << id << " in " << image.id << " has no disc in the truth";
      EXPECT_NEAR( disc->second.px, std::abs( area ) / 2, 0.03 * std::abs( area ) / 2 + 0.3 ) << id << " in " << image.id;
      const bool wholeInTruth = disc->second.inView >= 0.97 && disc->second.inSun >= 0.97;
      // the white area must match the projected disc (the window held all of it and nothing else)
      const bool wholeInImage = std::abs( sum - std::abs( area ) / 2 ) <= 0.05 * std::abs( area ) / 2;
      ++discs;
      agreeing += wholeInTruth == wholeInImage ? 1 : 0;
      if ( !wholeInImage )
      {
        std::cout << id << " in " << image.id << ": white area " << sum << " px, projected disc " << std::abs( area ) / 2 << " px (shaded or partly hidden: in view "
                  << disc->second.inView << ", in sunlight " << disc->second.inSun << " says the truth), skipped\n";
        continue;
      }
      worst = std::max( worst, ( found - centroid ).norm() );
      EXPECT_LT( ( found - centroid ).norm(), 0.01 ) << id << " in " << image.id;
      ++measured;
    }
  }
  EXPECT_GE( measured, 4 );
  std::cout << "target centroids: " << measured << " measured, worst " << worst << " px; the truth's disc whole or not as the rendering shows it: "
            << agreeing << " of " << discs << "\n";
  EXPECT_GE( agreeing, discs - 1 );
}

TEST( Simulation, OutputsAreCompleteAndConsistent )
{
  const std::filesystem::path &dir = aerialRun();
  for ( const char *name : { "block.geostation.json", "truth.geostation.json", "truth.gpkg", "terrain.tif", "simulation.json", "images/S0001.tif", "images/S0002.tif" } )
    EXPECT_TRUE( std::filesystem::exists( dir / name ) ) << name;
  for ( const auto &entry : std::filesystem::directory_iterator( dir ) )
    EXPECT_EQ( entry.path().filename().string().rfind( ".simulate-staging", 0 ), std::string::npos ) << "staging left behind";
  const Block truthBlock = Block::load( dir / "truth.geostation.json" );
  const Block noisy = Block::load( dir / "block.geostation.json" );
  ASSERT_EQ( truthBlock.images.size(), 3u );
  ASSERT_EQ( noisy.images.size(), 3u );
  EXPECT_EQ( truthBlock.crs, "EPSG:32617" );
  for ( const BlockImage &image : noisy.images )
  {
    ASSERT_TRUE( image.exterior && image.exterior->sigma );
    EXPECT_NO_THROW( requireReadableImageFile( noisy, image ) );
  }
  const TruthTable truth = readTruth( dir / "truth.gpkg" );
  EXPECT_GT( truth.control.size(), 4u );
  EXPECT_GT( truth.objects.size(), 4u );
  EXPECT_GT( truth.roads, 10 );
  EXPECT_NE( truth.controlCrsName.find( "UTM zone 17N" ), std::string::npos ) << truth.controlCrsName;
  // image truth = projection of the truth point with the exact orientation
  const Dem terrain( ( dir / "terrain.tif" ).string() );
  int checked = 0;
  for ( const auto &[key, pixel] : truth.imageTruth )
  {
    const auto point = truth.control.count( key.first ) ? truth.control.find( key.first ) : truth.objects.find( key.first );
    if ( point == truth.objects.end() )
      continue; // a road vertex
    const BlockImage &image = truthBlock.image( key.second );
    const GroundProjection p = projectGroundToPixel( truthBlock.cameraOf( image ), *image.exterior, point->second );
    ASSERT_TRUE( p.ok() && p.inFrame );
    EXPECT_LT( ( p.pixelInImage - pixel ).norm(), 1e-6 );
    ++checked;
  }
  EXPECT_GT( checked, 10 );
  // ground points sit on the written terrain
  for ( const auto &[id, point] : truth.control )
    EXPECT_NEAR( *terrain.heightAt( point.x(), point.y() ), point.z(), 1e-4 ) << id;
}

TEST( Simulation, SameSeedSameOutputOtherSeedOtherOutput )
{
  const auto run = []( uint32_t seed, const std::string &name )
  {
    SimulationOptions options;
    options.preset = SurveyPreset::Highway;
    options.seed = seed;
    options.outputDir = tempDir( name );
    options.stations = 2;
    options.cameras = 2;
    options.imageWidth = 320;
    options.imageHeight = 240;
    options.degradation.noiseSigma = 2.0;
    options.degradation.blurSigmaPx = 0.5;
    simulateSurvey( options );
    return options.outputDir;
  };
  const std::filesystem::path a = run( 5, "seed-a" ), b = run( 5, "seed-b" ), c = run( 6, "seed-c" );
  const auto bytes = []( const std::filesystem::path &p )
  {
    std::ifstream in( p, std::ios::binary );
    return std::string( std::istreambuf_iterator<char>( in ), {} );
  };
  EXPECT_EQ( bytes( a / "block.geostation.json" ), bytes( b / "block.geostation.json" ) );
  EXPECT_EQ( cv::norm( readRgb( a / "images/S0001_FL.tif" ), readRgb( b / "images/S0001_FL.tif" ), cv::NORM_INF ), 0.0 );
  EXPECT_NE( bytes( a / "block.geostation.json" ), bytes( c / "block.geostation.json" ) );
  EXPECT_GT( cv::norm( readRgb( a / "images/S0001_FL.tif" ), readRgb( c / "images/S0001_FL.tif" ), cv::NORM_L1 ), 0.0 );
  for ( const auto &dir : { a, b, c } )
    std::filesystem::remove_all( dir );
}

TEST( Simulation, HighwayRigMatchesItsDescription )
{
  SimulationOptions options;
  options.preset = SurveyPreset::Highway;
  options.seed = 2;
  options.outputDir = "unused";
  options.stations = 30;
  options.cameras = 6;
  const RigSettings settings = rigSettings( options );
  const SceneRequest request = sceneRequest( options, settings );
  const BuiltScene built = buildScene( request );
  Block truth, noisy;
  buildRig( options, settings, built, truth, noisy );
  ASSERT_EQ( truth.stations.size(), 30u );
  ASSERT_EQ( truth.images.size(), 180u );
  // forward stereo base about 2 m, cameras 2-3 m above the road, stations 5 m apart
  const ExteriorOrientation &fl = *truth.image( "S0001_FL" ).exterior, &fr = *truth.image( "S0001_FR" ).exterior;
  EXPECT_NEAR( ( fl.projectionCentre - fr.projectionCentre ).norm(), 2.0, 0.01 );
  const double ground = *built.scene->terrain().heightAt( fl.projectionCentre.x(), fl.projectionCentre.y() );
  EXPECT_GT( fl.projectionCentre.z() - ground, 2.0 );
  EXPECT_LT( fl.projectionCentre.z() - ground, 3.0 );
  EXPECT_NEAR( ( truth.image( "S0002_FL" ).exterior->projectionCentre - fl.projectionCentre ).head<2>().norm(), 5.0, 0.05 );
  // the forward camera looks along the road, slightly down
  EXPECT_GT( fl.viewingDirection().x(), 0.95 );
  EXPECT_LT( fl.viewingDirection().z(), 0.0 );
  // GNSS/INS errors: per station, shared by its cameras; statistics near the sigmas
  double sumX = 0.0;
  for ( size_t i = 0; i < truth.images.size(); i += 6 )
  {
    const Eigen::Vector3d d = noisy.images[i].exterior->projectionCentre - truth.images[i].exterior->projectionCentre;
    sumX += d.x() * d.x();
  }
  const double rmsX = std::sqrt( sumX / 30 );
  EXPECT_GT( rmsX, 0.05 );
  EXPECT_LT( rmsX, 0.17 );
  EXPECT_DOUBLE_EQ( noisy.images[0].exterior->sigma->x, 0.10 );
}

TEST( Simulation, HighwayImageTruthSeesPolesAndRoadVertices )
{
  SimulationOptions options;
  options.preset = SurveyPreset::Highway;
  options.seed = 4;
  options.outputDir = tempDir( "highway" );
  options.stations = 3;
  simulateSurvey( options );
  const TruthTable truth = readTruth( options.outputDir / "truth.gpkg" );
  int poles = 0, roadVertices = 0;
  for ( const auto &[key, pixel] : truth.imageTruth )
  {
    poles += key.first.rfind( "pole_", 0 ) == 0 ? 1 : 0;
    roadVertices += key.first.find( ':' ) != std::string::npos ? 1 : 0;
    EXPECT_TRUE( pixel.x() >= 0 && pixel.y() >= 0 && pixel.x() < 640 && pixel.y() < 480 );
  }
  EXPECT_GT( poles, 3 );
  EXPECT_GT( roadVertices, 200 );
  std::filesystem::remove_all( options.outputDir );
}

TEST( Simulation, BadInputGetsOneClearMessageAndNoOutput )
{
  const auto expectMessage = []( SimulationOptions options, const std::string &fragment )
  {
    options.outputDir = tempDir( "bad" );
    try
    {
      simulateSurvey( options );
      ADD_FAILURE() << "no error for " << fragment;
    }
    catch ( const std::invalid_argument &e )
    {
      EXPECT_NE( std::string( e.what() ).find( fragment ), std::string::npos ) << e.what();
    }
    EXPECT_FALSE( std::filesystem::exists( options.outputDir / "block.geostation.json" ) );
    std::filesystem::remove_all( options.outputDir );
  };
  SimulationOptions options;
  options.stations = 2;
  options.imageWidth = 64;
  options.imageHeight = 48;
  SimulationOptions bad = options;
  bad.cameras = 9;
  expectMessage( bad, "2 to 6 cameras" );
  bad = options;
  bad.degradation.jpegQuality = 101;
  expectMessage( bad, "JPEG quality" );
  bad = options;
  bad.demPath = "/nonexistent/dem.tif";
  expectMessage( bad, "dem.tif" );

  // a DEM far from the roads
  const std::string dem = syntheticterrain::tempPath( "sim-dem" );
  syntheticterrain::writeTerrain( dem, 200 );
  const std::filesystem::path roads = tempDir( "roads" ).string() + ".gpkg";
  const auto writeRoads = [&]( const char *crs, double x0, double y0 )
  {
    std::filesystem::remove( roads );
    GDALDatasetH ds = GDALCreate( GDALGetDriverByName( "GPKG" ), roads.string().c_str(), 0, 0, 0, GDT_Unknown, nullptr );
    OGRSpatialReferenceH srs = nullptr;
    if ( crs )
    {
      srs = OSRNewSpatialReference( nullptr );
      OSRSetFromUserInput( srs, crs );
      OSRSetAxisMappingStrategy( srs, OAMS_TRADITIONAL_GIS_ORDER );
    }
    OGRLayerH layer = GDALDatasetCreateLayer( ds, "roads", srs, wkbLineString, nullptr );
    OGRFeatureH f = OGR_F_Create( OGR_L_GetLayerDefn( layer ) );
    OGRGeometryH g = OGR_G_CreateGeometry( wkbLineString );
    const double step = crs && std::string( crs ) == "EPSG:4326" ? 1e-5 : 1.0;
    for ( int k = 0; k <= 300; k += 10 )
      OGR_G_AddPoint_2D( g, x0 + k * step, y0 - 0.3 * k * step );
    OGR_F_SetGeometryDirectly( f, g );
    EXPECT_EQ( OGR_L_CreateFeature( layer, f ), OGRERR_NONE );
    OGR_F_Destroy( f );
    GDALClose( ds );
    if ( srs )
      OSRDestroySpatialReference( srs );
  };
  writeRoads( "EPSG:32633", 900000.0, 5000000.0 );
  bad = options;
  bad.demPath = dem;
  bad.roadsPath = roads.string();
  expectMessage( bad, "does not overlap the DEM" );
  writeRoads( nullptr, 400050.0, 4999900.0 );
  expectMessage( bad, "has no CRS" );

  // roads in another CRS are reprojected, and the run works on the DEM
  double lon = 0, lat = 0;
  {
    OGRSpatialReferenceH utm = OSRNewSpatialReference( nullptr ), wgs = OSRNewSpatialReference( nullptr );
    OSRSetFromUserInput( utm, "EPSG:32633" );
    OSRSetFromUserInput( wgs, "EPSG:4326" );
    OSRSetAxisMappingStrategy( utm, OAMS_TRADITIONAL_GIS_ORDER );
    OSRSetAxisMappingStrategy( wgs, OAMS_TRADITIONAL_GIS_ORDER );
    OGRCoordinateTransformationH ct = OCTNewCoordinateTransformation( utm, wgs );
    double x = 400060.0, y = 4999850.0;
    OCTTransform( ct, 1, &x, &y, nullptr );
    lon = x;
    lat = y;
    OCTDestroyCoordinateTransformation( ct );
    OSRDestroySpatialReference( utm );
    OSRDestroySpatialReference( wgs );
  }
  writeRoads( "EPSG:4326", lon, lat );
  SimulationOptions good = options;
  good.demPath = dem;
  good.roadsPath = roads.string();
  good.outputDir = tempDir( "reprojected" );
  const SimulationSummary summary = simulateSurvey( good );
  bool noted = false;
  for ( const std::string &note : summary.notes )
    noted = noted || note.find( "roads reprojected" ) != std::string::npos;
  EXPECT_TRUE( noted );
  EXPECT_NE( summary.crs.find( "UTM zone 33N" ), std::string::npos );
  std::filesystem::remove_all( good.outputDir );
  std::filesystem::remove( roads );
  std::filesystem::remove( dem );
}

TEST( Simulation, CameraLookingAtTheSkyIsRefused )
{
  SceneRequest request;
  request.extentMin = Eigen::Vector2d( -100, -100 );
  request.extentMax = Eigen::Vector2d( 100, 100 );
  const BuiltScene built = buildScene( request );
  Block block;
  block.crs = built.crs;
  Camera camera;
  camera.id = "c";
  camera.width = 64;
  camera.height = 48;
  camera.f = 60;
  camera.cx = 32;
  camera.cy = 24;
  block.cameras.push_back( camera );
  BlockImage image;
  image.id = "up";
  image.cameraId = "c";
  ExteriorOrientation eo;
  eo.projectionCentre = Eigen::Vector3d( built.siteCentre.x(), built.siteCentre.y(), 260.0 );
  eo.omegaDeg = 180.0; // looks straight up
  image.exterior = eo;
  block.images.push_back( image );
  try
  {
    requireGroundInView( *built.scene, block, block.images.front() );
    ADD_FAILURE() << "a camera looking up was accepted";
  }
  catch ( const std::invalid_argument &e )
  {
    EXPECT_NE( std::string( e.what() ).find( "looks at the sky only" ), std::string::npos );
  }
  block.images.front().exterior->omegaDeg = 0.0; // nadir
  EXPECT_NO_THROW( requireGroundInView( *built.scene, block, block.images.front() ) );
}

TEST( Degradation, EachFaultDoesWhatItSays )
{
  const cv::Mat grey( 200, 300, CV_32FC3, cv::Scalar( 0.4f, 0.4f, 0.4f ) );
  DegradationOptions none;
  cv::Mat clean = degradeAndQuantise( grey, none, 1 );
  EXPECT_EQ( clean.at<cv::Vec3b>( 10, 10 )[0], 102 );
  DegradationOptions noisy;
  noisy.noiseSigma = 5.0;
  cv::Mat n = degradeAndQuantise( grey, noisy, 1 );
  cv::Scalar mean, stddev;
  cv::meanStdDev( n, mean, stddev );
  EXPECT_NEAR( stddev[0], 5.0, 0.3 );
  DegradationOptions bright;
  bright.exposure = 3.0;
  EXPECT_EQ( degradeAndQuantise( grey, bright, 1 ).at<cv::Vec3b>( 5, 5 )[0], 255 ); // clipped
  DegradationOptions bits;
  bits.bitErrorRate = 0.01;
  cv::Mat b = degradeAndQuantise( grey, bits, 1 );
  int flipped = 0;
  for ( int r = 0; r < b.rows; ++r )
    for ( int c = 0; c < b.cols; ++c )
      flipped += ( b.at<cv::Vec3b>( r, c )[0] == 0 || b.at<cv::Vec3b>( r, c )[0] == 255 ) ? 1 : 0;
  EXPECT_NEAR( flipped / 60000.0, 0.01, 0.002 );
  DegradationOptions vignette;
  vignette.vignetting = 0.4;
  cv::Mat v = degradeAndQuantise( grey, vignette, 1 );
  EXPECT_EQ( v.at<cv::Vec3b>( 100, 150 )[0], 102 );
  EXPECT_NEAR( v.at<cv::Vec3b>( 0, 0 )[0], 102 * 0.6, 2 );
  DegradationOptions jpeg;
  jpeg.jpegQuality = 50;
  jpeg.noiseSigma = 8.0;
  noisy.noiseSigma = 8.0;
  EXPECT_GT( cv::norm( degradeAndQuantise( grey, jpeg, 1 ), degradeAndQuantise( grey, noisy, 1 ), cv::NORM_L1 ), 0.0 );
  DegradationOptions bad;
  bad.vignetting = 2.0;
  EXPECT_THROW( bad.validate(), std::invalid_argument );
}

TEST( SimulatedObliquePhoto, MonoplottedTruthPointsLandOnTheTruth )
{
  // The oblique_photo preset with an exact orientation: every visible truth
  // point's true pixel, monoplotted against terrain.tif, comes back within
  // 1 mm; and the monoplotter agrees that these points are visible.
  SimulationOptions options;
  options.preset = SurveyPreset::ObliquePhoto;
  options.seed = 8;
  options.outputDir = tempDir( "oblique" );
  options.imageWidth = 640;
  options.imageHeight = 480;
  options.poseNoiseScale = 0.0;
  simulateSurvey( options );
  const Block block = Block::load( options.outputDir / "block.geostation.json" );
  const BlockImage &image = block.images.front();
  const OrientedImage oriented( block.cameraOf( image ), *image.exterior );
  const Dem dem( ( options.outputDir / "terrain.tif" ).string() );
  const CrsTransform same( block.crs, block.crs );
  const Monoplotter monoplotter( oriented, dem, same );
  const TruthTable truth = readTruth( options.outputDir / "truth.gpkg" );
  // road vertices: their 3-D positions from the roads layer
  std::map<std::string, Eigen::Vector3d> vertices;
  {
    GDALDatasetH ds = GDALOpenEx( ( options.outputDir / "truth.gpkg" ).string().c_str(), GDAL_OF_VECTOR, nullptr, nullptr, nullptr );
    OGRLayerH roads = GDALDatasetGetLayerByName( ds, "roads" );
    while ( OGRFeatureH f = OGR_L_GetNextFeature( roads ) )
    {
      OGRGeometryH g = OGR_F_GetGeometryRef( f );
      for ( int v = 0; v < OGR_G_GetPointCount( g ); ++v )
        vertices[std::string( OGR_F_GetFieldAsString( f, 0 ) ) + ":" + std::to_string( v )] = Eigen::Vector3d( OGR_G_GetX( g, v ), OGR_G_GetY( g, v ), OGR_G_GetZ( g, v ) );
      OGR_F_Destroy( f );
    }
    GDALClose( ds );
  }
  int checked = 0;
  double worst = 0.0;
  for ( const auto &[key, pixel] : truth.imageTruth )
  {
    Eigen::Vector3d point;
    if ( truth.control.count( key.first ) )
      point = truth.control.at( key.first );
    else if ( vertices.count( key.first ) )
      point = vertices.at( key.first );
    else
      continue; // objects stand above the ground
    const MonoplotPoint ground = monoplotter.imageToGround( pixel, false );
    ASSERT_TRUE( ground.ok() ) << key.first << ": " << ground.message;
    worst = std::max( worst, ( ground.world - point ).norm() );
    EXPECT_LT( ( ground.world - point ).norm(), 0.001 ) << key.first;
    EXPECT_TRUE( monoplotter.groundToImage( point ).visible ) << key.first;
    ++checked;
  }
  EXPECT_GT( checked, 300 );
  std::cout << "oblique photo: " << checked << " truth points monoplotted, worst " << worst * 1000 << " mm\n";
  std::filesystem::remove_all( options.outputDir );
}

TEST( SimulatedObliquePhoto, ScannedFilmInnerOrientationFromTheRenderedMarks )
{
  // The scanned-film variant: the fiducial marks found automatically in the
  // rendered scan give back the true scan affine, and with it the truth
  // points project to their true pixels.
  SimulationOptions options;
  options.preset = SurveyPreset::ObliquePhoto;
  options.scannedFilm = true;
  options.seed = 21;
  options.outputDir = tempDir( "film" );
  options.degradation.noiseSigma = 1.5;
  simulateSurvey( options );
  const Block truth = Block::load( options.outputDir / "truth.geostation.json" );
  Block noisy = Block::load( options.outputDir / "block.geostation.json" );
  const BlockImage &truthImage = truth.images.front();
  ASSERT_TRUE( truthImage.innerOrientation.has_value() );
  EXPECT_FALSE( noisy.images.front().innerOrientation.has_value() );
  const Camera &camera = truth.cameraOf( truthImage );
  ASSERT_EQ( camera.fiducials.size(), 8u );

  FiducialDetectionOptions detection;
  detection.scanPixelMm = *camera.pixelSizeMm;
  detection.markDiameterPx = kFiducialDiameterPx;
  const std::array<DetectedFiducial, 4> found = detectCornerFiducials( ( options.outputDir / truthImage.path ).string(), detection );
  const std::array<std::string, 4> ids = cornerFiducialIds( camera.fiducials );
  std::vector<FiducialMeasurement> measured;
  for ( int k = 0; k < 4; ++k )
  {
    ASSERT_TRUE( found[k].found() ) << "corner " << k << ": " << found[k].message << " at " << found[k].pixelInImage.transpose() << " score " << found[k].score;
    measured.push_back( { ids[k], found[k].pixelInImage } );
    const Eigen::Vector2d photo = std::find_if( camera.fiducials.begin(), camera.fiducials.end(), [&]( const Fiducial &f ) { return f.id == ids[k]; } )->photoMm;
    const Eigen::Vector2d expected = truth.orientedImage( truthImage ).scanFromNominal(
                                       Eigen::Vector2d( camera.cx + photo.x() / *camera.pixelSizeMm, camera.cy - photo.y() * camera.aspect / *camera.pixelSizeMm ) );
    EXPECT_LT( ( found[k].pixelInImage - expected ).norm(), 0.1 ) << ids[k] << " found at " << found[k].pixelInImage.transpose() << ", truth " << expected.transpose();
  }
  const InnerOrientationSummary io = innerOrientation( camera.fiducials, measured );
  ASSERT_TRUE( io.ok() ) << io.message;
  // the estimated affine against the true one, over the whole frame (mm)
  double worstMm = 0.0;
  for ( const Eigen::Vector2d &corner : { Eigen::Vector2d( 0, 0 ), Eigen::Vector2d( camera.width, 0 ), Eigen::Vector2d( 0, camera.height ),
                                         Eigen::Vector2d( camera.width, camera.height ) } )
  {
    const Eigen::Vector3d h( corner.x(), corner.y(), 1.0 );
    worstMm = std::max( worstMm, ( io.photoFromPixel * h - truthImage.innerOrientation->photoFromPixel * h ).norm() );
  }
  EXPECT_LT( worstMm, 0.01 ) << "estimated vs true scan affine at the frame corners";

  // with the measured inner orientation, the truth points land on their true scan pixels
  BlockImage &image = noisy.images.front();
  image.innerOrientation = ImageInnerOrientation { io.photoFromPixel, io.sigma0Mm };
  image.exterior = truthImage.exterior; // exact exterior, to see the inner orientation alone
  const OrientedImage oriented = noisy.orientedImage( image );
  const TruthTable table = readTruth( options.outputDir / "truth.gpkg" );
  int checked = 0;
  double worstPx = 0.0;
  for ( const auto &[key, pixel] : table.imageTruth )
    if ( table.control.count( key.first ) )
    {
      const GroundProjection p = oriented.projectGroundToPixel( table.control.at( key.first ) );
      ASSERT_TRUE( p.ok() );
      worstPx = std::max( worstPx, ( p.pixelInImage - pixel ).norm() );
      ++checked;
    }
  EXPECT_GT( checked, 10 );
  EXPECT_LT( worstPx, 0.1 );
  std::cout << "scanned film: affine within " << worstMm * 1000 << " um at the corners; " << checked << " control points within " << worstPx << " px\n";
  std::filesystem::remove_all( options.outputDir );
}

TEST( Simulation, GeographicDemWithHolesAndAnOrthophoto )
{
  // A DEM in geographic coordinates with nodata holes: the block gets the UTM
  // zone of its centre, the holes are filled, and the rendered terrain agrees
  // with the DEM; an orthophoto in another CRS drapes the ground.
  const std::string dem = syntheticterrain::tempPath( "sim-geodem" );
  // 0.0002 deg cells (about 16 x 22 m) around 13.7 E, 45.1 N
  syntheticterrain::writeDem( dem.c_str(), "EPSG:4326", { 13.68, 0.0002, 0.0, 45.12, 0.0, -0.0002 }, 200, 200,
                              []( double lon, double lat ) { return 150.0 + 900.0 * ( lon - 13.68 ) - 600.0 * ( lat - 45.1 ); },
                              []( int c, int r ) { return c >= 90 && c < 94 && r >= 100 && r < 103; } );
  // a checkerboard orthophoto in Web Mercator covering the DEM
  const std::string ortho = syntheticterrain::tempPath( "sim-ortho" );
  {
    GDALDatasetH ds = GDALCreate( GDALGetDriverByName( "GTiff" ), ortho.c_str(), 400, 400, 3, GDT_Byte, nullptr );
    double gt[6] = { 1524077.0, 5.0, 0.0, 5638278.0, 0.0, -5.0 }; // EPSG:3857, 2 km around 13.70 E, 45.10 N
    GDALSetGeoTransform( ds, gt );
    OGRSpatialReferenceH srs = OSRNewSpatialReference( nullptr );
    OSRSetFromUserInput( srs, "EPSG:3857" );
    GDALSetSpatialRef( ds, srs );
    OSRDestroySpatialReference( srs );
    std::vector<uint8_t> band( 400 * 400 );
    for ( int b = 1; b <= 3; ++b )
    {
      for ( int r = 0; r < 400; ++r )
        for ( int c = 0; c < 400; ++c )
          band[r * 400 + c] = static_cast<uint8_t>( ( ( r / 10 + c / 10 ) % 2 ) ? 200 : 40 + 20 * b );
      ASSERT_EQ( GDALRasterIO( GDALGetRasterBand( ds, b ), GF_Write, 0, 0, 400, 400, band.data(), 400, 400, GDT_Byte, 0, 0 ), CE_None );
    }
    GDALClose( ds );
  }
  SimulationOptions options;
  options.preset = SurveyPreset::AerialStereo;
  options.seed = 3;
  options.stations = 2;
  options.imageWidth = 400;
  options.imageHeight = 400;
  options.groundPixelSizeM = 0.5;
  options.demPath = dem;
  options.orthoPath = ortho;
  options.outputDir = tempDir( "geodem" );
  const SimulationSummary summary = simulateSurvey( options );
  EXPECT_EQ( summary.crs, "EPSG:32633" );
  bool geographicNote = false, filledNote = false, orthoNote = false;
  for ( const std::string &note : summary.notes )
  {
    geographicNote = geographicNote || note.find( "the DEM is geographic" ) != std::string::npos;
    filledNote = filledNote || note.find( "DEM cells without data were filled" ) != std::string::npos;
    orthoNote = orthoNote || note.find( "orthophoto" ) != std::string::npos;
  }
  EXPECT_TRUE( geographicNote );
  EXPECT_TRUE( filledNote );
  EXPECT_TRUE( orthoNote );
  // the terrain written agrees with the DEM (hole cells: with the filled values) at control points
  const Dem source( dem ), terrain( ( options.outputDir / "terrain.tif" ).string() );
  const CrsTransform toGeographic( "EPSG:32633", "EPSG:4326" );
  const TruthTable truth = readTruth( options.outputDir / "truth.gpkg" );
  ASSERT_GT( truth.control.size(), 3u );
  for ( const auto &[id, p] : truth.control )
  {
    const Eigen::Vector3d geo = toGeographic.transform( p );
    ASSERT_TRUE( source.heightAt( geo.x(), geo.y() ).has_value() ) << id;
    // the terrain grid samples the DEM surface; on this plane-like DEM they agree closely (roads flatten it a little)
    EXPECT_NEAR( p.z(), *source.heightAt( geo.x(), geo.y() ), 1.0 ) << id;
    EXPECT_NEAR( *terrain.heightAt( p.x(), p.y() ), p.z(), 1e-4 ) << id;
  }
  // Monoplotting against the geographic DEM itself (holes filled): the true
  // pixels of the control points, and of the middle of the hole, land on
  // the DEM's surface and project back to the same pixels.
  const Block block = Block::load( options.outputDir / "block.geostation.json" );
  const CrsTransform fromGeographic( "EPSG:4326", "EPSG:32633" );
  const double holeLon = 13.68 + 92.0 * 0.0002, holeLat = 45.12 - 101.5 * 0.0002;
  const Eigen::Vector3d holeMiddle = fromGeographic.transform( { holeLon, holeLat, 0.0 } );
  std::vector<Eigen::Vector3d> targets { { holeMiddle.x(), holeMiddle.y(), *source.heightAt( holeLon, holeLat ) } };
  for ( const auto &[id, p] : truth.control )
    targets.push_back( p );
  int monoplotted = 0, holeSeen = 0;
  for ( const BlockImage &image : block.images )
  {
    const OrientedImage oriented( block.cameraOf( image ), *image.exterior );
    const Monoplotter monoplotter( oriented, source, toGeographic );
    for ( size_t k = 0; k < targets.size(); ++k )
    {
      const GroundProjection g = oriented.projectGroundToPixel( targets[k] );
      if ( !g.ok() || !g.inFrame )
        continue;
      const MonoplotPoint ground = monoplotter.imageToGround( g.pixelInImage, true );
      ASSERT_TRUE( ground.ok() ) << ground.message;
      const Eigen::Vector3d geo = toGeographic.transform( ground.world );
      EXPECT_NEAR( ground.world.z(), *source.heightAt( geo.x(), geo.y() ), 1e-3 );
      EXPECT_LT( ( oriented.projectGroundToPixel( ground.world ).pixelInImage - g.pixelInImage ).norm(), 0.01 );
      EXPECT_LT( ( ground.world - targets[k] ).norm(), k == 0 ? 0.01 : 3.0 ); // control points sit on the road-flattened terrain
      EXPECT_GT( ground.sigmaM.z(), 0.0 );
      ++monoplotted;
      holeSeen += k == 0;
    }
  }
  EXPECT_GE( monoplotted, 4 );
  EXPECT_GE( holeSeen, 1 );
  std::cout << "geographic DEM with holes: " << monoplotted << " points monoplotted, the hole's middle in " << holeSeen << " image(s)\n";
  std::filesystem::remove_all( options.outputDir );
  std::filesystem::remove( dem );
  std::filesystem::remove( ortho );
}
