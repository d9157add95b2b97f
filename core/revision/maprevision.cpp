/***************************************************************************
  maprevision.cpp - an existing road map held against a new stereo pair
 ***************************************************************************/
#include "revision/maprevision.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <map>
#include <stdexcept>

#include "extraction/crossprofile.h"
#include "extraction/greytiles.h"
#include "adjustment/intersection.h"
#include "extraction/pairmapping.h"
#include "geometry/polyline.h"
#include "revision/samplecheck.h"

namespace geostation
{

  std::string revisionStatusName( RevisionStatus status )
  {
    switch ( status )
    {
      case RevisionStatus::Confirmed: return "confirmed";
      case RevisionStatus::Moved: return "moved";
      case RevisionStatus::NotFound: return "not_found";
      case RevisionStatus::Outside: return "outside";
      case RevisionStatus::Occluded: return "occluded";
      case RevisionStatus::InvalidGeometry: return "invalid_geometry";
    }
    return "not_found";
  }

  std::optional<RevisionStatus> revisionStatusFromName( const std::string &name )
  {
    for ( const RevisionStatus s : { RevisionStatus::Confirmed, RevisionStatus::Moved, RevisionStatus::NotFound, RevisionStatus::Outside, RevisionStatus::Occluded,
                                     RevisionStatus::InvalidGeometry } )
      if ( revisionStatusName( s ) == name )
        return s;
    return std::nullopt;
  }

  void MapRevisionOptions::check() const
  {
    network.coincident.check();
    if ( shiftMaxM && !( *shiftMaxM > 0.0 ) )
      throw std::invalid_argument( "the largest shift of a road must be positive (metres)" );
    if ( !( toleranceM >= 0.0 ) || !( sampleSpacingPx >= 0.0 ) || !( newGapM >= 0.0 ) || majorityHalfWindow < 0 || !( occlusionClearanceM >= 0.0 ) || !( longProfileM >= 0.0 ) )
      throw std::invalid_argument( "the map's tolerance, the sample spacing, the new roads' gap, the majority window, the occlusion clearance and the long profiles' length must not be negative" );
  }

  double RevisedPiece::lengthM() const
  {
    return polylineLengthXY( course );
  }

  double MapRevisionSummary::lengthM( RevisionStatus status ) const
  {
    double length = 0.0;
    for ( const RevisedPiece &p : pieces )
      if ( p.status == status )
        length += p.lengthM();
    return length;
  }

  using revision::PairView;
  using revision::Sample;

  namespace
  {
    struct MeasuredVertex
    {
      Eigen::Vector3d point = Eigen::Vector3d::Zero(), sigmaM = Eigen::Vector3d::Zero();
      bool stereo = false;
    };

    //! The mapped course every `spacingM` (XY), at the map's height or, without one, the terrain's.
    std::vector<Eigen::Vector3d> samplesAlong( const MapRoad &road, double spacingM, const OrientedPairMapping &mapping, const TerrainHeight &terrain )
    {
      std::vector<Eigen::Vector3d> out;
      const auto height = [&]( const Eigen::Vector3d &p ) {
        if ( std::isfinite( p.z() ) )
          return p.z();
        const std::optional<double> z = terrain ? terrain( p.x(), p.y() ) : std::nullopt;
        return z ? *z : mapping.meanHeightM();
      };
      for ( size_t i = 0; i + 1 < road.vertices.size(); ++i )
      {
        const Eigen::Vector3d &a = road.vertices[i], &b = road.vertices[i + 1];
        const int n = std::max( 1, static_cast<int>( std::ceil( ( b - a ).head<2>().norm() / spacingM ) ) );
        for ( int k = 0; k < n; ++k )
        {
          Eigen::Vector3d p = a + ( b - a ) * ( static_cast<double>( k ) / n );
          p.z() = height( std::isfinite( a.z() ) && std::isfinite( b.z() ) ? p : Eigen::Vector3d( p.x(), p.y(), std::nan( "" ) ) );
          out.push_back( p );
        }
      }
      Eigen::Vector3d last = road.vertices.back();
      last.z() = height( last );
      out.push_back( last );
      return out;
    }

    /**
     * A confirmed or moved sample in 3-D: where the road in B crosses the
     * epipolar direction at 35 degrees or more, the rays through its band
     * centres in both images are intersected (the across-road offsets pin
     * the conjugate points); where it runs along the epipolar direction they
     * do not, and the point is the first image's ray on the terrain (its
     * height the terrain's, with the terrain's spread as sigma).
     */
    MeasuredVertex measured( const Sample &s, const Eigen::Vector2d &alongB, const PairView &pair )
    {
      MeasuredVertex v;
      const OrientedImage &a = pair.mapping.imageA(), &b = pair.mapping.imageB();
      const std::optional<Ray> ray = a.worldRayFromPixel( s.foundA );
      if ( ray && std::abs( ray->direction.z() ) > 1e-9 )
      {
        const auto at = [&]( double z ) { return b.projectGroundToPixel( ray->origin + ( z - ray->origin.z() ) / ray->direction.z() * ray->direction ); };
        const GroundProjection low = at( s.ground.z() - 20.0 ), high = at( s.ground.z() + 20.0 );
        const Eigen::Vector2d epipolar = high.pixelInImage - low.pixelInImage;
        if ( low.ok() && high.ok() && epipolar.norm() > 1e-6 && std::abs( epipolar.normalized().x() * alongB.y() - epipolar.normalized().y() * alongB.x() ) >= std::sin( 35.0 * M_PI / 180.0 ) )
        {
          const IntersectionSummary x = intersectRays( { { &a, s.foundA, 0.5 }, { &b, s.foundB, 0.5 } } );
          if ( x.ok() )
          {
            v.point = x.point;
            v.sigmaM = x.covariance.diagonal().cwiseMax( 0.0 ).cwiseSqrt();
            v.stereo = true;
            return v;
          }
        }
      }
      const std::optional<Eigen::Vector3d> ground = pair.mapping.groundPoint( a, s.foundA );
      v.point = ground ? *ground : s.ground;
      v.sigmaM = Eigen::Vector3d( 0.5 * pair.groundPixelM, 0.5 * pair.groundPixelM, pair.terrainSigmaM );
      return v;
    }

    //! The pieces of one road: runs of one status, moved and confirmed ones measured again.
    void piecesOf( size_t road, const std::vector<Sample> &samples, const std::vector<RevisionStatus> &status, const PairView &pair, std::vector<RevisedPiece> &out )
    {
      // the samples' places along the map road: they lie on its course, every vertex among them
      std::vector<double> along( samples.size(), 0.0 );
      for ( size_t k = 1; k < samples.size(); ++k )
        along[k] = along[k - 1] + ( samples[k].ground - samples[k - 1].ground ).head<2>().norm();
      for ( size_t from = 0; from < samples.size(); )
      {
        size_t to = from + 1;
        while ( to < samples.size() && status[to] == status[from] )
          ++to;
        RevisedPiece piece;
        piece.road = road;
        piece.status = status[from];
        std::vector<double> shifts;
        int agree = 0;
        // the map's course, including the first sample of the next run, so that the pieces join
        for ( size_t k = from; k < std::min( to + 1, samples.size() ); ++k )
        {
          piece.course.push_back( samples[k].ground );
          piece.alongMapM.push_back( along[k] );
        }
        piece.fromM = along[from];
        piece.toM = along[std::min( to, samples.size() - 1 )];
        for ( size_t k = from; k < to; ++k )
        {
          agree += samples[k].status == piece.status;
          if ( samples[k].status == RevisionStatus::Moved )
            shifts.push_back( samples[k].shiftM );
        }
        piece.evidence = static_cast<double>( agree ) / ( to - from );
        if ( !shifts.empty() )
        {
          std::nth_element( shifts.begin(), shifts.begin() + shifts.size() / 2, shifts.end() );
          piece.shiftM = shifts[shifts.size() / 2];
        }
        if ( piece.status == RevisionStatus::Confirmed || piece.status == RevisionStatus::Moved )
        {
          // the stretch's own samples, measured; the others of the run (a car, a shadow) are left out
          std::vector<Eigen::Vector3d> course, sigma;
          std::vector<bool> stereo;
          std::vector<double> alongMap;
          for ( size_t k = from; k < to; ++k )
            if ( samples[k].status == piece.status )
            {
              const MeasuredVertex v = measured( samples[k], directionAt( samples, k, false ), pair );
              course.push_back( v.point );
              sigma.push_back( v.sigmaM );
              stereo.push_back( v.stereo );
              alongMap.push_back( along[k] );
            }
          if ( course.size() >= 2 )
          {
            piece.course = std::move( course );
            piece.sigmaM = std::move( sigma );
            piece.heightByStereo = std::move( stereo );
            piece.alongMapM = std::move( alongMap );
          }
        }
        if ( piece.course.size() >= 2 )
          out.push_back( std::move( piece ) );
        from = to;
      }
    }

    //! The stretches of the extracted lines (at least 3 vertices) farther than `gapM` from every map road and every revised course.
    std::vector<NetworkLine> newRoads( const NetworkIntersectionSummary &network, const std::vector<MapRoad> &map, const std::vector<RevisedPiece> &pieces, double gapM )
    {
      std::vector<const std::vector<Eigen::Vector3d> *> known;
      for ( const MapRoad &road : map )
        known.push_back( &road.vertices );
      for ( const RevisedPiece &piece : pieces )
        known.push_back( &piece.course );
      std::vector<NetworkLine> out;
      for ( const NetworkLine &line : network.lines )
      {
        NetworkLine stretch;
        stretch.sourceLine = line.sourceLine;
        const auto flush = [&]() {
          if ( stretch.vertices.size() >= 3 )
            out.push_back( stretch );
          stretch.vertices.clear();
        };
        for ( const NetworkVertex &v : line.vertices )
        {
          bool explained = false;
          for ( const std::vector<Eigen::Vector3d> *course : known )
            explained = explained || nearestOnPolylineXY( *course, v.point.head<2>() ).distance <= gapM;
          if ( explained )
            flush();
          else
            stretch.vertices.push_back( v );
        }
        flush();
      }
      return out;
    }

    bool validRoad( const MapRoad &road )
    {
      for ( size_t i = 1; i < road.vertices.size(); ++i )
        if ( road.vertices[i].head<2>().allFinite() && road.vertices[0].head<2>().allFinite() && ( road.vertices[i] - road.vertices[0] ).head<2>().norm() > 1e-6 )
          return true;
      return false;
    }
  } // namespace

  std::vector<Eigen::Vector3d> spliceCourse( const std::vector<Eigen::Vector3d> &line, const std::vector<Eigen::Vector3d> &course )
  {
    if ( line.size() < 2 || course.size() < 2 )
      throw std::invalid_argument( "a line and a course of at least two points are needed to splice" );
    // the arc position along `line` of the point nearest p (XY), and the segment it lies on
    const auto project = [&]( const Eigen::Vector3d &p ) {
      const NearestOnPolyline<Eigen::Vector2d> n = nearestOnPolylineXY( line, p.head<2>() );
      double at = n.t * ( line[n.segment + 1] - line[n.segment] ).head<2>().norm(); // the arc position along `line`
      for ( size_t i = 0; i < n.segment; ++i )
        at += ( line[i + 1] - line[i] ).head<2>().norm();
      return std::make_pair( at, n.segment );
    };
    std::vector<Eigen::Vector3d> stretch = course;
    auto first = project( stretch.front() ), last = project( stretch.back() );
    if ( first.first > last.first )
    {
      std::reverse( stretch.begin(), stretch.end() );
      std::swap( first, last );
    }
    std::vector<Eigen::Vector3d> out( line.begin(), line.begin() + first.second + 1 );
    out.insert( out.end(), stretch.begin(), stretch.end() );
    out.insert( out.end(), line.begin() + last.second + 1, line.end() );
    return out;
  }

  MapRevisionSummary reviseRoads( std::shared_ptr<const RasterReader> readerA, std::shared_ptr<const RasterReader> readerB, const OrientedImage &a, const OrientedImage &b,
                                  const std::vector<MapRoad> &map, const MapRevisionOptions &options, const Progress &progress )
  {
    using Range = std::optional<std::pair<double, double>>;
    const auto range = []( const RasterReader &r ) { return r.eightBit() ? Range() : Range( greyRangeOf( r ) ); };
    const Range rangeA = range( *readerA ), rangeB = range( *readerB );
    PairMatchWindows matching( matchWindowsOf( readerA, readerB, rangeA, rangeB ), readerA->size(), readerB->size() );
    return reviseRoads( greyTilesOf( readerA, rangeA ), greyTilesOf( readerB, rangeB ), matching, a, b, map, options, progress );
  }

  MapRevisionSummary reviseRoads( const MatchImage &imageA, const MatchImage &imageB, const OrientedImage &a, const OrientedImage &b, const std::vector<MapRoad> &map,
                                  const MapRevisionOptions &options, const Progress &progress )
  {
    if ( imageA.empty() || imageB.empty() || imageA.windowed() || imageB.windowed() )
      throw std::invalid_argument( "map revision needs both images of the pair, whole" );
    PairMatchWindows matching( imageA, imageB );
    return reviseRoads( GreyTiles( imageA.grey() ), GreyTiles( imageB.grey() ), matching, a, b, map, options, progress );
  }

  MapRevisionSummary reviseRoads( const GreyTiles &greyA, const GreyTiles &greyB, PairMatchWindows &matching, const OrientedImage &a, const OrientedImage &b,
                                  const std::vector<MapRoad> &map, const MapRevisionOptions &options, const Progress &progress )
  {
    using namespace revision;
    options.check();
    const auto start = std::chrono::steady_clock::now();
    MapRevisionSummary summary;
    // 1. the pair's own extraction: its terrain height, its widths in pixels and the roads it finds (or only the first two)
    RoadNetworkOptions network = options.network;
    network.extract = options.findNewRoads;
    const double extractionShare = options.findNewRoads ? 0.7 : 0.1;
    summary.extraction = extractRoadNetwork( greyA, greyB, matching, &a, &b, network, progress.part( 0.0, extractionShare ) );
    if ( summary.extraction.extraction.cancelled )
    {
      summary.cancelled = true;
      return summary;
    }
    const OrientedPairMapping mapping( a, b, summary.extraction.meanHeightM, options.network.terrain );
    PairView pair { greyA, greyB, mapping, options.network.coincident.extraction.object };
    if ( summary.extraction.widthsFromMetres )
    {
      pair.object.minWidthPx = summary.extraction.widthsFromMetres->minPx;
      pair.object.maxWidthPx = summary.extraction.widthsFromMetres->maxPx;
    }
    pair.object.minContrast = summary.extraction.minContrast;
    pair.terrainSigmaM = summary.extraction.terrainEstimate ? 1.4826 * summary.extraction.terrainEstimate->spreadM : 0.0;
    pair.groundPixelM = summary.extraction.widthsFromMetres ? summary.extraction.widthsFromMetres->groundPixelM
                                                          : widthsPxFor( a, summary.extraction.meanHeightM, { 1.0, 1.0 } ).groundPixelM;
    summary.groundPixelM = pair.groundPixelM;
    summary.shiftMaxM = options.shiftMaxM ? *options.shiftMaxM
                        : options.network.roadWidthM ? 1.5 * options.network.roadWidthM->second
                                                     : 40.0 * pair.groundPixelM;
    summary.toleranceM = options.toleranceM;
    pair.tolerancePx = std::max( 2.0, options.toleranceM / pair.groundPixelM );
    pair.shiftMaxPx = summary.shiftMaxM / pair.groundPixelM;
    pair.longAlongPx = options.longProfileM / pair.groundPixelM;
    const double spacingPx = options.sampleSpacingPx > 0.0 ? options.sampleSpacingPx : std::max( 4.0, pair.object.minWidthPx );

    // 2. each map road checked along its course, split where its status changes
    for ( size_t r = 0; r < map.size(); ++r )
    {
      if ( !progress.report( extractionShare + ( 1.0 - extractionShare ) * r / map.size(), "map road " + std::to_string( r + 1 ) + " of " + std::to_string( map.size() ) ) )
      {
        summary.cancelled = true;
        return summary;
      }
      if ( !validRoad( map[r] ) )
      {
        RevisedPiece invalid;
        invalid.road = r;
        invalid.status = RevisionStatus::InvalidGeometry;
        invalid.course = map[r].vertices;
        invalid.alongMapM.assign( invalid.course.size(), 0.0 );
        summary.pieces.push_back( invalid );
        continue;
      }
      std::vector<Sample> samples;
      for ( const Eigen::Vector3d &g : samplesAlong( map[r], spacingPx * pair.groundPixelM, mapping, options.network.terrain ) )
      {
        Sample s;
        s.ground = g;
        const double margin = pair.object.maxWidthPx + pair.tolerancePx;
        s.status = inFrame( a, g, s.inA, margin ) && inFrame( b, g, s.inB, margin ) ? RevisionStatus::NotFound : RevisionStatus::Outside;
        s.occluded = s.status != RevisionStatus::Outside && options.surface &&
                     ( hiddenFrom( a, g, options.surface, options.occlusionClearanceM ) || hiddenFrom( b, g, options.surface, options.occlusionClearanceM ) );
        samples.push_back( s );
      }
      for ( size_t i = 0; i < samples.size(); ++i )
        if ( samples[i].status != RevisionStatus::Outside )
          check( samples[i], directionAt( samples, i, true ), directionAt( samples, i, false ), pair );
      settleShifts( samples );
      requireContinuity( samples );
      confirmThroughJunctions( samples, pair );
      for ( Sample &s : samples )
        if ( s.status == RevisionStatus::NotFound && s.occluded )
          s.status = RevisionStatus::Occluded; // hidden, not gone
      summary.samples += static_cast<int>( samples.size() );
      piecesOf( r, samples, majorityStatus( samples, options.majorityHalfWindow ), pair, summary.pieces );
    }

    // 3. the roads the extraction found that no map road explains
    const double gapM = options.newGapM > 0.0 ? options.newGapM : std::max( 3.0 * options.toleranceM, 10.0 * pair.groundPixelM );
    if ( options.findNewRoads )
      summary.newRoads = newRoads( summary.extraction.network, map, summary.pieces, gapM );
    summary.seconds = std::chrono::duration<double>( std::chrono::steady_clock::now() - start ).count();
    return summary;
  }

} // namespace geostation
