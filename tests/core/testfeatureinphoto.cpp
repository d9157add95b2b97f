// A map line shown in an oriented photo with its hidden parts marked
// (issue 18, item 4): the simulator's oblique photo over hilly terrain, the
// road's centre line from the truth, the terrain as the DEM. The simulator
// says which road vertices its rendering shows (image_truth); the runs must
// agree with it wherever the terrain, not a tree or a house, decides.
#include <gtest/gtest.h>

#include <filesystem>
#include <iostream>
#include <unistd.h>

#include <gdal.h>
#include <ogr_api.h>

#include "dem/linevisibility.h"
#include "workstation/pointmeasurer.h"
#include "geometry/crs.h"
#include "io/block.h"
#include "simulation/surveysimulator.h"
#include "simulationtruth.h"

using namespace geostation;

namespace
{
  std::vector<Eigen::Vector3d> readRoad( const std::filesystem::path &gpkg, const std::string &id )
  {
    GDALDatasetH ds = GDALOpenEx( gpkg.string().c_str(), GDAL_OF_VECTOR, nullptr, nullptr, nullptr );
    OGRLayerH layer = GDALDatasetGetLayerByName( ds, "roads" );
    std::vector<Eigen::Vector3d> line;
    OGRFeatureH f;
    while ( ( f = OGR_L_GetNextFeature( layer ) ) )
    {
      if ( OGR_F_GetFieldAsString( f, OGR_F_GetFieldIndex( f, "id" ) ) == id )
      {
        OGRGeometryH g = OGR_F_GetGeometryRef( f );
        for ( int i = 0; i < OGR_G_GetPointCount( g ); ++i )
          line.emplace_back( OGR_G_GetX( g, i ), OGR_G_GetY( g, i ), OGR_G_GetZ( g, i ) );
      }
      OGR_F_Destroy( f );
    }
    GDALClose( ds );
    return line;
  }
} // namespace

TEST( LineVisibility, HiddenRunsAgreeWithTheRenderedPhoto )
{
  SimulationOptions options;
  options.preset = SurveyPreset::ObliquePhoto;
  options.seed = 5;
  options.outputDir = std::filesystem::temp_directory_path() / ( "geostation-linevisibility-" + std::to_string( ::getpid() ) );
  std::filesystem::remove_all( options.outputDir );
  simulateSurvey( options );
  const Block block = Block::load( options.outputDir / "truth.geostation.json" );
  const BlockImage &image = block.images.front();
  const OrientedImage oriented = block.orientedImage( image );
  const TruthTable truth = readTruth( options.outputDir / "truth.gpkg" );
  const Dem dem( ( options.outputDir / "terrain.tif" ).string() );
  const CrsTransform same( block.crs, dem.crsWkt() );
  const Monoplotter mono( oriented, dem, same );

  int agree = 0, compared = 0, truthHidden = 0, hiddenRuns = 0, visibleRuns = 0;
  for ( const std::string road : { "R1-centre-001", "R2-centre-001", "R3-centre-001" } )
  {
    const std::vector<Eigen::Vector3d> line = readRoad( options.outputDir / "truth.gpkg", road );
    ASSERT_GE( line.size(), 10u ) << road;
    const std::vector<LineVisibilityRun> runs = lineVisibilityRuns( oriented, &mono, line, 2.0 );
    for ( const LineVisibilityRun &run : runs )
    {
      EXPECT_GE( run.pixels.size(), 2u );
      ( run.hidden ? hiddenRuns : visibleRuns ) += 1;
    }
    // each truth vertex in the frame: hidden or not by the runs (the run point on it), against the rendering
    for ( size_t i = 0; i < line.size(); ++i )
    {
      const GroundProjection p = oriented.projectGroundToPixel( line[i] );
      if ( !p.ok() || !p.inFrame )
        continue;
      int flags = 0;
      bool hidden = false;
      for ( const LineVisibilityRun &run : runs )
        for ( const Eigen::Vector2d &px : run.pixels )
          if ( ( px - p.pixelInImage ).norm() < 0.01 )
          {
            flags |= run.hidden ? 2 : 1;
            hidden = run.hidden;
          }
      if ( flags == 0 || flags == 3 )
        continue; // not drawn (behind the camera) or on the boundary of two runs
      const bool rendered = truth.imageTruth.count( { road + ":" + std::to_string( i ), image.id } ) > 0;
      ++compared;
      truthHidden += rendered ? 0 : 1;
      agree += ( hidden == !rendered ) ? 1 : 0;
    }
  }
  std::cout << compared << " road vertices in the photo, " << truthHidden << " not shown by the rendering; the runs agree on " << agree << " ("
            << hiddenRuns << " hidden runs, " << visibleRuns << " visible)\n";
  EXPECT_GE( compared, 100 );
  EXPECT_GE( truthHidden, 10 ); // the scene hides part of its roads behind hills
  EXPECT_GT( hiddenRuns, 0 );
  EXPECT_GE( agree, compared * 9 / 10 );

  // without a DEM nothing is hidden, and a line behind the camera draws nothing
  const std::vector<Eigen::Vector3d> road = readRoad( options.outputDir / "truth.gpkg", "R1-centre-001" );
  for ( const LineVisibilityRun &run : lineVisibilityRuns( oriented, nullptr, road ) )
    EXPECT_FALSE( run.hidden );
  const Eigen::Vector3d behind = oriented.exterior().projectionCentre - 50.0 * oriented.exterior().worldDirectionFromCamera( Eigen::Vector3d( 0, 0, -1 ) );
  EXPECT_TRUE( lineVisibilityRuns( oriented, &mono, { behind, behind + Eigen::Vector3d( 5, 0, 0 ) } ).empty() );
  EXPECT_THROW( lineVisibilityRuns( oriented, &mono, road, 0.0 ), std::invalid_argument );
  std::filesystem::remove_all( options.outputDir );
}

TEST( LineVisibility, ALineDigitisedInThePhotoIsDensifiedOnTheTerrain )
{
  SimulationOptions options;
  options.preset = SurveyPreset::ObliquePhoto;
  options.seed = 5;
  options.outputDir = std::filesystem::temp_directory_path() / ( "geostation-densify-" + std::to_string( ::getpid() ) );
  std::filesystem::remove_all( options.outputDir );
  simulateSurvey( options );
  const Block block = Block::load( options.outputDir / "truth.geostation.json" );
  const OrientedImage oriented = block.orientedImage( block.images.front() );
  const Dem dem( ( options.outputDir / "terrain.tif" ).string() );
  const CrsTransform same( block.crs, dem.crsWkt() );
  const Monoplotter mono( oriented, dem, same );
  // two clicks 300 px apart across the hilly middle of the photo
  const VertexObservation from { block.images.front().id, &oriented, Eigen::Vector2d( 300.0, 500.0 ), 0.5 };
  const Eigen::Vector2d to( 600.0, 520.0 );
  const MeasuredVertex a = demVertex( from, mono ), b = demVertex( { from.imageId, &oriented, to, 0.5 }, mono );
  ASSERT_TRUE( a.ok() && b.ok() );
  const std::vector<MeasuredVertex> between = demVerticesBetween( from, to, mono, 20.0 );
  EXPECT_EQ( between.size(), 15u ); // 301 px in 16 pieces
  double worstOffTerrain = 0.0, chordOffTerrain = 0.0;
  for ( size_t k = 0; k < between.size(); ++k )
  {
    const MeasuredVertex &v = between[k];
    EXPECT_EQ( v.method, VertexMethod::MonoplotDem );
    EXPECT_GT( v.sigmaM.norm(), 0.0 );
    // on the terrain, and seen where it was taken on the image segment
    worstOffTerrain = std::max( worstOffTerrain, std::abs( v.point.z() - *dem.heightAt( v.point.x(), v.point.y() ) ) );
    const Eigen::Vector2d pixel = oriented.projectGroundToPixel( v.point ).pixelInImage;
    const Eigen::Vector2d expected = from.pixelInImage + ( to - from.pixelInImage ) * ( static_cast<double>( k + 1 ) / 16.0 );
    EXPECT_LT( ( pixel - expected ).norm(), 0.01 );
    // the straight chord between the clicks, where this vertex lies
    const double t = static_cast<double>( k + 1 ) / 16.0;
    const Eigen::Vector3d chord = a.point + t * ( b.point - a.point );
    chordOffTerrain = std::max( chordOffTerrain, std::abs( chord.z() - *dem.heightAt( chord.x(), chord.y() ) ) );
  }
  std::cout << "densified: " << between.size() << " vertices at most " << worstOffTerrain << " m off the terrain; the straight chord up to " << chordOffTerrain << " m\n";
  EXPECT_LT( worstOffTerrain, 0.05 );
  EXPECT_GT( chordOffTerrain, 1.0 ); // on hilly ground the chord is no map of the line
  EXPECT_THROW( demVerticesBetween( from, to, mono, 0.0 ), std::invalid_argument );
  std::filesystem::remove_all( options.outputDir );
}
