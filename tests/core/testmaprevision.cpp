/***************************************************************************
  testmaprevision.cpp - an old road map held against a new pair
  -------------------------------------------------------------------------
  On the painted road scenes (paintedroads.h, not the simulator), with a
  map made from their truth and changed on purpose: the main road as it
  is, the winding road mapped three road widths (24 m) north of where it
  runs, the dark road left out, and a road mapped across the fields where
  there is none. With the defaults.
 ***************************************************************************/
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <optional>

#include <gtest/gtest.h>

#include "matching/matchimage.h"
#include "paintedroads.h"
#include "revision/maprevision.h"
#include "revision/samplecheck.h"
#include "revisionlengths.h"

using namespace geostation;
using geostation::testing::lengthOf;
using namespace geostation::paintedroads;

namespace
{
  MapRoad mapRoad( const std::vector<Eigen::Vector2d> &xy, const Eigen::Vector2d &shift = Eigen::Vector2d::Zero() )
  {
    MapRoad road;
    for ( const Eigen::Vector2d &p : xy )
      road.vertices.emplace_back( p.x() + shift.x(), p.y() + shift.y(), std::nan( "" ) );
    return road;
  }

  struct Revised
  {
    PaintedRoadPair pair;
    std::vector<MapRoad> map;
    MapRevisionSummary summary;
  };

  const Revised &revised()
  {
    static const Revised r = []
    {
      Revised out;
      out.pair = paintedRoadPair( scenes()[1] ); // 0.5 m
      const std::vector<PaintedRoad> &roads = out.pair.roads;
      out.map.push_back( mapRoad( roads[0].centre ) );                                    // as it is
      out.map.push_back( mapRoad( roads[1].centre, Eigen::Vector2d( 0.0, 3.0 * roads[1].widthM ) ) ); // mapped 24 m north
      out.map.push_back( mapRoad( { { -80.0, -195.0 }, { 140.0, -165.0 } } ) );             // not there: south of the main road, 100 m from it
      const OrientedImage a( out.pair.camera, out.pair.exterior[0] ), b( out.pair.camera, out.pair.exterior[1] );
      out.summary = reviseRoads( MatchImage( out.pair.grey[0] ), MatchImage( out.pair.grey[1] ), a, b, out.map, MapRevisionOptions() );
      return out;
    }();
    return r;
  }

  //! Points every metre along a polyline (XY) that both photos see.
  std::vector<Eigen::Vector3d> seenPoints( const PaintedRoadPair &pair, const std::vector<Eigen::Vector2d> &line )
  {
    const OrientedImage a( pair.camera, pair.exterior[0] ), b( pair.camera, pair.exterior[1] );
    std::vector<Eigen::Vector3d> out;
    for ( size_t i = 0; i + 1 < line.size(); ++i )
    {
      const int n = static_cast<int>( std::ceil( ( line[i + 1] - line[i] ).norm() ) );
      for ( int k = 0; k < n; ++k )
      {
        const Eigen::Vector2d xy = line[i] + ( line[i + 1] - line[i] ) * ( static_cast<double>( k ) / n );
        const Eigen::Vector3d g( xy.x(), xy.y(), pair.groundM );
        const GroundProjection pa = a.projectGroundToPixel( g ), pb = b.projectGroundToPixel( g );
        const auto inside = [&]( const GroundProjection &p ) {
          return p.ok() && p.pixelInImage.x() > 30 && p.pixelInImage.y() > 30 && p.pixelInImage.x() < pair.camera.width - 30 && p.pixelInImage.y() < pair.camera.height - 30;
        };
        if ( inside( pa ) && inside( pb ) )
          out.push_back( g );
      }
    }
    return out;
  }

  double distanceXY( const Eigen::Vector3d &p, const std::vector<Eigen::Vector3d> &line )
  {
    double best = 1e300;
    for ( size_t i = 0; i + 1 < line.size(); ++i )
    {
      const Eigen::Vector2d a = line[i].head<2>(), ab = line[i + 1].head<2>() - a;
      const double t = ab.squaredNorm() > 0 ? std::clamp( ( p.head<2>() - a ).dot( ab ) / ab.squaredNorm(), 0.0, 1.0 ) : 0.0;
      best = std::min( best, ( a + t * ab - p.head<2>() ).norm() );
    }
    return best;
  }

  std::vector<Eigen::Vector3d> ground( const std::vector<Eigen::Vector2d> &xy, double z )
  {
    std::vector<Eigen::Vector3d> out;
    for ( const Eigen::Vector2d &p : xy )
      out.emplace_back( p.x(), p.y(), z );
    return out;
  }
} // namespace

TEST( MapRevision, UnchangedRoadIsConfirmed )
{
  const Revised &r = revised();
  const auto [confirmed, seen] = lengthOf( r.summary, 0, RevisionStatus::Confirmed );
  std::printf( "main road: %.0f of %.0f m confirmed\n", confirmed, seen );
  ASSERT_GT( seen, 100.0 );
  EXPECT_GE( confirmed, 0.95 * seen );
  // measured again in 3-D, on the road's centre line, with sigmas
  for ( const RevisedPiece &p : r.summary.pieces )
    if ( p.road == 0 && p.status == RevisionStatus::Confirmed )
    {
      ASSERT_EQ( p.sigmaM.size(), p.course.size() );
      for ( const Eigen::Vector3d &v : p.course )
        EXPECT_LT( distanceXY( v, ground( r.pair.roads[0].centre, r.pair.groundM ) ), 1.5 );
    }
}

TEST( MapRevision, EachPieceSaysWhereItLiesAlongTheMapRoad )
{
  // what merging the revisions of overlapping pairs cuts by: the pieces of a road follow one another along it
  // from 0 to its length, and each vertex is placed between its piece's ends
  const Revised &r = revised();
  for ( size_t road = 0; road < r.map.size(); ++road )
  {
    double length = 0.0;
    for ( size_t i = 1; i < r.map[road].vertices.size(); ++i )
      length += ( r.map[road].vertices[i] - r.map[road].vertices[i - 1] ).head<2>().norm();
    double reached = 0.0;
    for ( const RevisedPiece &p : r.summary.pieces )
      if ( p.road == road )
      {
        EXPECT_NEAR( p.fromM, reached, 1e-6 ) << "road " << road;
        ASSERT_EQ( p.alongMapM.size(), p.course.size() );
        for ( size_t k = 0; k < p.alongMapM.size(); ++k )
        {
          EXPECT_GE( p.alongMapM[k], p.fromM - 1e-9 );
          EXPECT_LE( p.alongMapM[k], p.toM + 1e-9 );
          if ( k > 0 )
          {
            EXPECT_GE( p.alongMapM[k], p.alongMapM[k - 1] );
          }
        }
        reached = p.toM;
      }
    EXPECT_NEAR( reached, length, 1e-6 ) << "road " << road;
  }
}

TEST( MapRevision, ShiftedRoadIsMovedToWhereItRuns )
{
  const Revised &r = revised();
  const auto [moved, seen] = lengthOf( r.summary, 1, RevisionStatus::Moved );
  std::vector<double> off;
  double sum2 = 0.0;
  for ( const RevisedPiece &p : r.summary.pieces )
    if ( p.road == 1 && p.status == RevisionStatus::Moved )
      for ( const Eigen::Vector3d &v : p.course )
      {
        off.push_back( distanceXY( v, ground( r.pair.roads[1].centre, r.pair.groundM ) ) );
        sum2 += off.back() * off.back();
      }
  const double rms = off.empty() ? 0.0 : std::sqrt( sum2 / off.size() );
  std::sort( off.begin(), off.end() );
  std::printf( "winding road mapped 24 m off: %.0f of %.0f m moved, new course %.2f m RMS from the truth (median %.2f, 90 %% %.2f, worst %.2f m)\n", moved, seen, rms,
               off.empty() ? 0.0 : off[off.size() / 2], off.empty() ? 0.0 : off[off.size() * 9 / 10], off.empty() ? 0.0 : off.back() );
  ASSERT_GT( seen, 100.0 );
  EXPECT_GE( moved, 0.9 * seen );
  EXPECT_LT( rms, 1.0 );
  const double confirmed = lengthOf( r.summary, 1, RevisionStatus::Confirmed ).first;
  std::printf( "  of the rest %.0f m confirmed where it no longer runs\n", confirmed );
  EXPECT_LE( confirmed, 0.05 * seen );
}

TEST( MapRevision, RoadNotThereIsNotFound )
{
  const Revised &r = revised();
  const auto [notFound, seen] = lengthOf( r.summary, 2, RevisionStatus::NotFound );
  std::printf( "road mapped where there is none: %.0f of %.0f m not found\n", notFound, seen );
  ASSERT_GT( seen, 100.0 );
  EXPECT_GE( notFound, 0.9 * seen );
}

TEST( MapRevision, RoadMissingFromTheMapIsNew )
{
  const Revised &r = revised();
  std::vector<Eigen::Vector3d> newCourse;
  for ( const NetworkLine &l : r.summary.newRoads )
    for ( const NetworkVertex &v : l.vertices )
      newCourse.push_back( v.point );
  const std::vector<Eigen::Vector3d> truth = seenPoints( r.pair, r.pair.roads[2].centre );
  int covered = 0;
  for ( const Eigen::Vector3d &p : truth )
  {
    double best = 1e300;
    for ( const NetworkLine &l : r.summary.newRoads )
    {
      std::vector<Eigen::Vector3d> line;
      for ( const NetworkVertex &v : l.vertices )
        line.push_back( v.point );
      best = std::min( best, distanceXY( p, line ) );
    }
    covered += best <= r.pair.roads[2].widthM;
  }
  std::printf( "dark road left out of the map: %d of %zu m in NEW (%zu new lines)\n", covered, truth.size(), r.summary.newRoads.size() );
  ASSERT_GT( truth.size(), 100u );
  EXPECT_GE( covered, 0.9 * truth.size() );
}

TEST( MapRevision, BadGeometriesAndRoadsOutsideThePair )
{
  const Revised &base = revised();
  const OrientedImage a( base.pair.camera, base.pair.exterior[0] ), b( base.pair.camera, base.pair.exterior[1] );
  std::vector<MapRoad> map = { MapRoad(), mapRoad( { { 5.0, 5.0 }, { 5.0, 5.0 } } ), mapRoad( { { 50000.0, 0.0 }, { 50500.0, 0.0 } } ) };
  const MapRevisionSummary s = reviseRoads( MatchImage( base.pair.grey[0] ), MatchImage( base.pair.grey[1] ), a, b, map, MapRevisionOptions() );
  ASSERT_EQ( s.pieces.size(), 3u );
  EXPECT_EQ( s.pieces[0].status, RevisionStatus::InvalidGeometry );
  EXPECT_EQ( s.pieces[1].status, RevisionStatus::InvalidGeometry );
  EXPECT_EQ( s.pieces[2].status, RevisionStatus::Outside );
  MapRevisionOptions bad;
  bad.shiftMaxM = -1.0;
  EXPECT_THROW( reviseRoads( MatchImage( base.pair.grey[0] ), MatchImage( base.pair.grey[1] ), a, b, map, bad ), std::invalid_argument );
}

TEST( MapRevision, ARoadHiddenByABuildingIsOccludedNotGone )
{
  // the road mapped where there is none, with a building 25 m high over x = 0..50 m of it; the main road in the open
  const Revised &base = revised();
  const OrientedImage a( base.pair.camera, base.pair.exterior[0] ), b( base.pair.camera, base.pair.exterior[1] );
  const double groundM = base.pair.groundM;
  const auto heightAt = [groundM]( double x, double y ) { return x >= 0.0 && x <= 50.0 && y >= -200.0 && y <= -160.0 ? groundM + 25.0 : groundM; };
  const auto surfaceOf = [groundM]( std::function<double( double, double )> height ) {
    return [groundM, height]( const Ray &ray ) -> std::optional<Eigen::Vector3d> {
      // down the ray in 0.25 m steps from where it is 40 m above the ground to the first point under the surface
      if ( !( ray.direction.z() < 0.0 ) )
        return std::nullopt;
      for ( double t = ( ray.origin.z() - groundM - 40.0 ) / -ray.direction.z(); t < 1e5; t += 0.25 )
      {
        const Eigen::Vector3d p = ray.origin + t * ray.direction;
        if ( p.z() <= height( p.x(), p.y() ) )
          return p;
      }
      return std::nullopt;
    };
  };
  MapRevisionOptions options;
  options.findNewRoads = false;
  options.surface = surfaceOf( heightAt );
  const std::vector<MapRoad> map = { base.map[0], base.map[2] };
  const MapRevisionSummary s = reviseRoads( MatchImage( base.pair.grey[0] ), MatchImage( base.pair.grey[1] ), a, b, map, options );
  double occluded = 0.0, notFound = 0.0;
  for ( const RevisedPiece &p : s.pieces )
    if ( p.road == 1 )
    {
      ( p.status == RevisionStatus::Occluded ? occluded : notFound ) += p.status == RevisionStatus::Outside ? 0.0 : p.lengthM();
      if ( p.status != RevisionStatus::Occluded )
        continue;
      for ( const Eigen::Vector3d &v : p.course )
      {
        EXPECT_TRUE( v.x() > -30.0 && v.x() < 80.0 ) << "occluded at x = " << v.x() << " m, far from the building";
      }
    }
  const auto [confirmed, seen] = lengthOf( s, 0, RevisionStatus::Confirmed );
  std::printf( "behind a building over 50 m of a road not there: %.0f m occluded, %.0f m not found; main road %.0f of %.0f m confirmed\n", occluded, notFound, confirmed,
               seen );
  EXPECT_GE( occluded, 40.0 );
  EXPECT_LE( occluded, 110.0 );
  EXPECT_GE( notFound, 70.0 ); // of the 154 m the pair sees
  EXPECT_GE( confirmed, 0.95 * seen ); // a road that is seen is confirmed, whatever the surface

  // open ground: nothing occluded
  options.surface = surfaceOf( [groundM]( double, double ) { return groundM; } );
  const MapRevisionSummary open = reviseRoads( MatchImage( base.pair.grey[0] ), MatchImage( base.pair.grey[1] ), a, b, map, options );
  for ( const RevisedPiece &p : open.pieces )
    EXPECT_NE( p.status, RevisionStatus::Occluded );
}

TEST( MapRevision, AMovedStretchIsSplicedIntoTheMapLine )
{
  const std::vector<Eigen::Vector3d> line = { { 0, 0, 1 }, { 10, 0, 1 }, { 20, 0, 1 }, { 30, 0, 1 }, { 40, 0, 1 } };
  // the road between x = 12 and x = 28 runs 3 m north now; given against the line's direction
  const std::vector<Eigen::Vector3d> course = { { 28, 3, 2 }, { 20, 3, 2 }, { 12, 3, 2 } };
  const std::vector<Eigen::Vector3d> spliced = spliceCourse( line, course );
  const std::vector<Eigen::Vector3d> expected = { { 0, 0, 1 }, { 10, 0, 1 }, { 12, 3, 2 }, { 20, 3, 2 }, { 28, 3, 2 }, { 30, 0, 1 }, { 40, 0, 1 } };
  ASSERT_EQ( spliced.size(), expected.size() );
  for ( size_t i = 0; i < expected.size(); ++i )
    EXPECT_TRUE( spliced[i].isApprox( expected[i] ) ) << i;
  EXPECT_THROW( spliceCourse( { { 0, 0, 0 } }, course ), std::invalid_argument );
}

TEST( MapRevision, ALongProfileSeesTheRoadPastACar )
{
  // a dark road 12 px wide on a bright field, a bright car 10 px long across the whole of it
  cv::Mat grey( 200, 200, CV_8U, cv::Scalar( 170 ) );
  cv::rectangle( grey, cv::Rect( 0, 94, 200, 12 ), cv::Scalar( 80 ), cv::FILLED );
  cv::rectangle( grey, cv::Rect( 95, 93, 10, 14 ), cv::Scalar( 175 ), cv::FILLED );
  const GreyTiles tiles( grey );
  LineObjectOptions object;
  object.polarity = 0;
  object.minWidthPx = 6.0;
  object.maxWidthPx = 30.0;
  object.minContrast = 20.0;
  const Eigen::Vector2d onTheCar( 100.0, 100.0 ), along( 1.0, 0.0 );
  EXPECT_TRUE( revision::bandsNear( tiles, onTheCar, along, object, 4.0 ).empty() ); // across the car: no road
  const std::vector<CrossSection> past = revision::bandsNear( tiles, onTheCar, along, object, 4.0, 16.0 );
  ASSERT_FALSE( past.empty() );
  EXPECT_NEAR( past.front().offsetPx, 0.0, 1.0 );
  EXPECT_NEAR( past.front().widthPx, 12.0, 2.0 );
  EXPECT_FALSE( revision::bandsNear( tiles, Eigen::Vector2d( 30.0, 100.0 ), along, object, 4.0 ).empty() ); // away from the car the short one does
}

TEST( MapRevision, ARoadRunsOnThroughAJunction )
{
  // a dark road 16 px wide along row 48, a side road joining it from below (columns 140-160), a darker strip of
  // field 10 px wide above it, 8 px of field between them; in the second image the road breaks off for 34 px
  cv::Mat junction( 160, 300, CV_8U, cv::Scalar( 190 ) );
  cv::rectangle( junction, cv::Rect( 0, 40, 300, 16 ), cv::Scalar( 90 ), cv::FILLED );
  cv::rectangle( junction, cv::Rect( 140, 56, 20, 104 ), cv::Scalar( 90 ), cv::FILLED );
  cv::rectangle( junction, cv::Rect( 0, 22, 300, 10 ), cv::Scalar( 50 ), cv::FILLED );
  cv::Mat broken = junction.clone();
  cv::rectangle( broken, cv::Rect( 198, 40, 34, 16 ), cv::Scalar( 190 ), cv::FILLED );
  Camera camera;
  camera.id = "one";
  camera.width = 300;
  camera.height = 160;
  camera.f = 300;
  camera.cx = 150;
  camera.cy = 80;
  const OrientedImage a( camera, ExteriorOrientation() ), b( camera, ExteriorOrientation() );
  const OrientedPairMapping mapping( a, b, -100.0 );
  LineObjectOptions object;
  object.polarity = 0;
  object.minWidthPx = 3.0;
  object.maxWidthPx = 30.0;
  object.minContrast = 20.0;
  for ( const bool isBroken : { false, true } )
  {
    const GreyTiles tiles( isBroken ? broken : junction );
    revision::PairView pair { tiles, tiles, mapping, object };
    pair.tolerancePx = 2.0;
    // as checked: the road confirmed, except across the side road's mouth (taken for the strip moved 16 px) or the break
    std::vector<revision::Sample> samples;
    for ( int x = 4; x <= 296; x += 4 )
    {
      revision::Sample s;
      s.inA = s.inB = s.foundA = s.foundB = Eigen::Vector2d( x, 48.0 );
      s.status = RevisionStatus::Confirmed;
      s.widthPx = 16.0;
      if ( x >= 136 && x <= 164 )
      {
        s.status = RevisionStatus::Moved;
        s.offsetPx = -21.0;
        s.widthPx = 10.0;
        s.shiftM = 21.0;
        s.foundA = s.foundB = Eigen::Vector2d( x, 27.0 );
      }
      if ( isBroken && x >= 200 && x <= 228 )
        s.status = RevisionStatus::NotFound;
      samples.push_back( s );
    }
    // a gap longer than twice the road's width is no junction's mouth: the same samples, but moved from 200 to 240 (48 px between the confirmed samples)
    std::vector<revision::Sample> longGap = samples;
    for ( revision::Sample &s : longGap )
      if ( s.inA.x() >= 200 && s.inA.x() <= 240 && s.status == RevisionStatus::Confirmed )
        s.status = RevisionStatus::Moved;
    revision::confirmThroughJunctions( longGap, pair );
    for ( const revision::Sample &s : longGap )
      if ( s.inA.x() >= 200 && s.inA.x() <= 240 )
      {
        EXPECT_NE( s.status, RevisionStatus::Confirmed ) << "a gap of 48 px, at " << s.inA.x();
      }
    revision::confirmThroughJunctions( samples, pair );
    for ( const revision::Sample &s : samples )
    {
      const double x = s.inA.x();
      if ( isBroken && x >= 200 && x <= 228 )
        EXPECT_EQ( s.status, RevisionStatus::NotFound ) << "no road where it breaks off, at " << x;
      else
      {
        EXPECT_EQ( s.status, RevisionStatus::Confirmed ) << ( isBroken ? "broken" : "junction" ) << ", at " << x;
        EXPECT_NEAR( s.offsetPx, 0.0, 1e-9 ) << x;
        EXPECT_NEAR( s.foundA.y(), 48.0, 1e-9 ) << x;
      }
    }
  }
}
