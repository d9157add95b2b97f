// A map feature drawn into an oriented photo (core dem/featureinphoto): the
// heights in the order the call states, a line cut at the boundary of what
// the photo can show, draped lines on the terrain, hidden runs. Then the
// simulator's oblique photo over hilly terrain, the roads' centre lines from
// the truth, the terrain as the DEM: the simulator says which road vertices
// its rendering shows (image_truth); the hidden runs must agree with it
// wherever the terrain, not a tree or a house, decides.
#include <gtest/gtest.h>

#include <filesystem>
#include <limits>
#include <memory>
#include <iostream>
#include <unistd.h>

#include <gdal.h>
#include <ogr_api.h>

#include "dem/featureinphoto.h"
#include "workstation/pointmeasurer.h"
#include "geometry/crs.h"
#include "io/block.h"
#include "simulation/surveysimulator.h"
#include "simulationtruth.h"
#include "syntheticterrain.h"
#include "vanrig.h"

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

namespace
{
  //! The simulator's oblique photo over hilly terrain (seed 5), simulated once for the tests that use it.
  struct ObliqueScene
  {
    std::filesystem::path dir = std::filesystem::temp_directory_path() / ( "geostation-featureinphoto-oblique-" + std::to_string( ::getpid() ) );
    Block block;
    std::unique_ptr<Dem> dem;
    ObliqueScene()
    {
      SimulationOptions options;
      options.preset = SurveyPreset::ObliquePhoto;
      options.seed = 5;
      options.outputDir = dir;
      std::filesystem::remove_all( dir );
      simulateSurvey( options );
      block = Block::load( dir / "truth.geostation.json" );
      dem = std::make_unique<Dem>( ( dir / "terrain.tif" ).string() );
    }
    ~ObliqueScene()
    {
      dem.reset();
      std::filesystem::remove_all( dir );
    }
  };

  const ObliqueScene &obliqueScene()
  {
    static const ObliqueScene s;
    return s;
  }

  //! The largest distance from a point of `from` to the nearest point of `to` (pixels).
  double farthestFrom( const std::vector<Eigen::Vector2d> &from, const std::vector<Eigen::Vector2d> &to )
  {
    double farthest = 0.0;
    for ( const Eigen::Vector2d &p : from )
    {
      double nearest = std::numeric_limits<double>::infinity();
      for ( const Eigen::Vector2d &q : to )
        nearest = std::min( nearest, ( p - q ).norm() );
      farthest = std::max( farthest, nearest );
    }
    return farthest;
  }

  using syntheticterrain::kX0;
  using syntheticterrain::kY0;

  //! Hilly synthetic terrain (2 m cells) and an oblique photo from 60 m above it, looking north and down.
  struct HillScene
  {
    std::string path = syntheticterrain::tempPath( "featureinphoto" );
    std::unique_ptr<Dem> dem;
    CrsTransform same { "EPSG:32633", "EPSG:32633" };
    std::unique_ptr<OrientedImage> image;
    std::unique_ptr<Monoplotter> mono;
    HillScene()
    {
      syntheticterrain::writeTerrain( path, 500 );
      dem = std::make_unique<Dem>( path );
      const Eigen::Vector3d centre( kX0 + 500.0, kY0 - 950.0, *dem->heightAt( kX0 + 500.0, kY0 - 950.0 ) + 60.0 );
      image = std::make_unique<OrientedImage>( vanrig::camera( DistortionModel::OpenCV ), vanrig::lookAt( centre, centre + Eigen::Vector3d( 0.0, 300.0, -120.0 ) ) );
      mono = std::make_unique<Monoplotter>( *image, *dem, same );
    }
    ~HillScene() { std::filesystem::remove( path ); }
  };

  HillScene &hills()
  {
    static HillScene s;
    return s;
  }

  constexpr double kNoZ = std::numeric_limits<double>::quiet_NaN();
} // namespace

TEST( FeatureInPhoto, HeightsInTheOrderTheCallStates )
{
  const HillScene &s = hills();
  const Eigen::Vector3d withZ( kX0 + 480.0, kY0 - 700.0, 123.0 ), inDem( kX0 + 520.0, kY0 - 700.0, kNoZ ), outside( kX0 - 100.0, kY0 - 700.0, kNoZ );
  const double demZ = *s.dem->heightAt( inDem.x(), inDem.y() );

  FeatureHeights zThenDem;
  zThenDem.dem = s.mono.get();
  const GroundPart both = groundPart( { withZ, inDem }, zThenDem );
  ASSERT_EQ( both.status, FeatureHeightStatus::Ok );
  EXPECT_DOUBLE_EQ( both.vertices[0].z(), 123.0 );
  EXPECT_NEAR( both.vertices[1].z(), demZ, 1e-9 );
  EXPECT_FALSE( both.draped ); // one vertex brought its own height
  EXPECT_TRUE( groundPart( { inDem, inDem + Eigen::Vector3d( 10, 0, 0 ) }, zThenDem ).draped );
  // a vertex outside the DEM with no plane to fall back on: refused, the first such vertex named
  const GroundPart off = groundPart( { withZ, inDem, outside }, zThenDem );
  EXPECT_EQ( off.status, FeatureHeightStatus::OutsideDem );
  EXPECT_EQ( off.failedVertex, 2u );
  EXPECT_TRUE( off.vertices.empty() );
  // ... with a plane it takes the plane's height
  FeatureHeights demThenPlane = zThenDem;
  demThenPlane.planeZ = 7.0;
  EXPECT_DOUBLE_EQ( groundPart( { outside }, demThenPlane ).vertices[0].z(), 7.0 );
  EXPECT_FALSE( groundPart( { inDem, outside }, demThenPlane ).draped );
  // the feature's Z not used: the DEM's height even where the vertex has one
  FeatureHeights demOnly = zThenDem;
  demOnly.featureZ = false;
  EXPECT_NEAR( groundPart( { withZ }, demOnly ).vertices[0].z(), *s.dem->heightAt( withZ.x(), withZ.y() ), 1e-9 );
  // no DEM: the plane (the Multiview overlay's Z = 0 for a 2-D layer, stated), else no height at all
  FeatureHeights plane;
  plane.planeZ = 0.0;
  EXPECT_DOUBLE_EQ( groundPart( { inDem }, plane ).vertices[0].z(), 0.0 );
  EXPECT_EQ( groundPart( { withZ, inDem }, FeatureHeights() ).status, FeatureHeightStatus::NoHeight );
  EXPECT_THROW( lineInPhoto( *s.image, off, zThenDem, LineInPhotoOptions() ), std::invalid_argument );
}

TEST( FeatureInPhoto, ALineLeavingThePhotoIsCutAtTheBoundaryNotAtItsLastPoint )
{
  // a line on the ground from ahead of the camera to behind it: it ends where the photo stops being able to show
  // it, found by bisection (the Multiview's overlay once ended it at the last densified point it could project,
  // and lines leaving the lens field were drawn straight from the boundary)
  const HillScene &s = hills();
  const Eigen::Vector3d c = s.image->exterior().projectionCentre;
  FeatureHeights plane;
  plane.planeZ = c.z() - 60.0;
  const GroundPart part = groundPart( { { c.x() + 5.0, c.y() + 200.0, kNoZ }, { c.x() + 5.0, c.y() - 200.0, kNoZ } }, plane );
  LineInPhotoOptions options;
  options.densifyPx = 40.0;
  const ProjectedGroundLine line = lineInPhoto( *s.image, part, plane, options );
  ASSERT_EQ( line.parts.size(), 1u );
  EXPECT_TRUE( line.clipped );
  // the boundary on the straight line, by bisection here
  const auto projects = [&]( double t ) { return s.image->projectGroundToPixel( part.vertices[0] + t * ( part.vertices[1] - part.vertices[0] ) ).ok(); };
  double in = 0.0, out = 1.0;
  ASSERT_TRUE( projects( in ) );
  ASSERT_FALSE( projects( out ) );
  for ( int k = 0; k < 60; ++k )
    ( projects( 0.5 * ( in + out ) ) ? in : out ) = 0.5 * ( in + out );
  const Eigen::Vector2d boundary = s.image->projectGroundToPixel( part.vertices[0] + in * ( part.vertices[1] - part.vertices[0] ) ).pixelInImage;
  EXPECT_LT( ( line.parts[0].back() - boundary ).norm(), 1e-3 * std::max( 1.0, boundary.norm() ) );
  // and densified up to there: no piece longer than asked for, however far into the distortion at the field's edge
  for ( size_t k = 1; k < line.parts[0].size(); ++k )
    EXPECT_LE( ( line.parts[0][k] - line.parts[0][k - 1] ).norm(), 40.0 + 1e-6 );
}

TEST( FeatureInPhoto, ALineWithoutHeightsFollowsTheTerrainAndHiddenRunsMeet )
{
  const HillScene &s = hills();
  FeatureHeights heights;
  heights.dem = s.mono.get();
  // a 2-D line across the hills: the points inserted take the DEM's heights, not the chord's
  const std::vector<Eigen::Vector3d> across { { kX0 + 300.0, kY0 - 600.0, kNoZ }, { kX0 + 700.0, kY0 - 600.0, kNoZ } };
  const GroundPart draped = groundPart( across, heights );
  ASSERT_TRUE( draped.draped );
  GroundPart chord = draped;
  chord.draped = false; // the same vertices as if they had brought their own heights: interpolated between them
  LineInPhotoOptions options;
  const ProjectedGroundLine onTerrain = lineInPhoto( *s.image, draped, heights, options ), onChord = lineInPhoto( *s.image, chord, heights, options );
  ASSERT_FALSE( onTerrain.parts.empty() );
  ASSERT_FALSE( onChord.parts.empty() );
  // every point drawn is the projection of a point of the line on the terrain (the line sampled every 0.1 m here)
  std::vector<Eigen::Vector2d> terrainCurve;
  for ( double t = 0.0; t <= 1.0; t += 0.1 / 400.0 )
  {
    const Eigen::Vector3d p = across[0] + t * ( across[1] - across[0] );
    const GroundProjection g = s.image->projectGroundToPixel( Eigen::Vector3d( p.x(), p.y(), *s.dem->heightAt( p.x(), p.y() ) ) );
    if ( g.ok() )
      terrainCurve.push_back( g.pixelInImage );
  }
  EXPECT_LT( farthestFrom( onTerrain.parts[0], terrainCurve ), 0.5 );
  EXPECT_GT( farthestFrom( onTerrain.parts[0], onChord.parts[0] ), 2.0 ); // on hills the chord is no drawing of the line

  // split where the terrain hides it: runs alternate, each hidden run meets a seen one at a shared pixel
  LineInPhotoOptions split;
  split.splitHidden = true;
  // (lines running north, away from the camera, over the hills: some behind crests)
  int runCount = 0, hidden = 0, met = 0;
  for ( double x = 200.0; x <= 800.0; x += 25.0 )
  {
    const std::vector<Eigen::Vector3d> away { { kX0 + x, kY0 - 850.0, kNoZ }, { kX0 + x, kY0 - 20.0, kNoZ } };
    const ProjectedGroundLine runs = lineInPhoto( *s.image, groundPart( away, heights ), heights, split );
    ASSERT_EQ( runs.hidden.size(), runs.parts.size() );
    runCount += static_cast<int>( runs.parts.size() );
    for ( size_t r = 0; r < runs.parts.size(); ++r )
    {
      if ( !runs.hidden[r] )
        continue;
      ++hidden;
      bool m = false;
      for ( size_t q = 0; q < runs.parts.size(); ++q )
        if ( !runs.hidden[q] && ( runs.parts[q].back() == runs.parts[r].front() || runs.parts[q].front() == runs.parts[r].back() ) )
        {
          m = true;
          break;
        }
      met += m ? 1 : 0;
      if ( !m )
      {
        std::cout << "x " << x << " run " << r << " of " << runs.parts.size() << " size " << runs.parts[r].size() << " from " << runs.parts[r].front().transpose() << " to " << runs.parts[r].back().transpose() << "\n";
        for ( size_t q = 0; q < runs.parts.size(); ++q )
          std::cout << "   " << q << " h" << runs.hidden[q] << " " << runs.parts[q].front().transpose() << " -> " << runs.parts[q].back().transpose() << "\n";
      }
    }
  }
  std::cout << runCount << " runs of 25 lines running away over the hills, " << hidden << " hidden\n";
  EXPECT_GT( hidden, 0 );
  EXPECT_EQ( met, hidden );
}

TEST( FeatureInPhoto, HiddenRunsAgreeWithTheRenderedPhoto )
{
  const ObliqueScene &scene = obliqueScene();
  const Block &block = scene.block;
  const BlockImage &image = block.images.front();
  const OrientedImage oriented = block.orientedImage( image );
  const TruthTable truth = readTruth( scene.dir / "truth.gpkg" );
  const Dem &dem = *scene.dem;
  const CrsTransform same( block.crs, dem.crsWkt() );
  const Monoplotter mono( oriented, dem, same );

  FeatureHeights heights;
  heights.dem = &mono;
  LineInPhotoOptions split;
  split.splitHidden = true;
  const auto runsOf = [&]( const std::vector<Eigen::Vector3d> &line, const FeatureHeights &h ) { return lineInPhoto( oriented, groundPart( line, h ), h, split ); };
  int agree = 0, compared = 0, truthHidden = 0, hiddenRuns = 0, visibleRuns = 0;
  for ( const std::string road : { "R1-centre-001", "R2-centre-001", "R3-centre-001" } )
  {
    const std::vector<Eigen::Vector3d> line = readRoad( scene.dir / "truth.gpkg", road );
    ASSERT_GE( line.size(), 10u ) << road;
    const ProjectedGroundLine runs = runsOf( line, heights );
    ASSERT_EQ( runs.hidden.size(), runs.parts.size() );
    for ( size_t r = 0; r < runs.parts.size(); ++r )
    {
      EXPECT_GE( runs.parts[r].size(), 2u );
      ( runs.hidden[r] ? hiddenRuns : visibleRuns ) += 1;
    }
    // each truth vertex in the frame: hidden or not by the runs (the run point on it), against the rendering
    for ( size_t i = 0; i < line.size(); ++i )
    {
      const GroundProjection p = oriented.projectGroundToPixel( line[i] );
      if ( !p.ok() || !p.inFrame )
        continue;
      int flags = 0;
      bool hidden = false;
      for ( size_t r = 0; r < runs.parts.size(); ++r )
        for ( const Eigen::Vector2d &px : runs.parts[r] )
          if ( ( px - p.pixelInImage ).norm() < 0.01 )
          {
            flags |= runs.hidden[r] ? 2 : 1;
            hidden = runs.hidden[r];
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
  const std::vector<Eigen::Vector3d> road = readRoad( scene.dir / "truth.gpkg", "R1-centre-001" );
  for ( const bool hidden : runsOf( road, FeatureHeights() ).hidden )
    EXPECT_FALSE( hidden );
  const Eigen::Vector3d behind = oriented.exterior().projectionCentre - 50.0 * oriented.exterior().worldDirectionFromCamera( Eigen::Vector3d( 0, 0, -1 ) );
  EXPECT_TRUE( runsOf( { behind, behind + Eigen::Vector3d( 5, 0, 0 ) }, heights ).parts.empty() );
  split.densifyPx = 0.0;
  EXPECT_THROW( runsOf( road, heights ), std::invalid_argument );
}

TEST( DemVertices, ALineDigitisedInThePhotoIsDensifiedOnTheTerrain )
{
  const ObliqueScene &scene = obliqueScene();
  const Block &block = scene.block;
  const OrientedImage oriented = block.orientedImage( block.images.front() );
  const Dem &dem = *scene.dem;
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
}
