/***************************************************************************
  maprevision.cpp - an existing road map held against a new stereo pair
 ***************************************************************************/
#include "revision/maprevision.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <stdexcept>

#include "extraction/crossprofile.h"
#include "extraction/greytiles.h"
#include "adjustment/intersection.h"
#include "extraction/pairmapping.h"

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
      case RevisionStatus::InvalidGeometry: return "invalid_geometry";
    }
    return "not_found";
  }

  void MapRevisionOptions::check() const
  {
    network.coincident.check();
    if ( shiftMaxM && !( *shiftMaxM > 0.0 ) )
      throw std::invalid_argument( "the largest shift of a road must be positive (metres)" );
    if ( !( toleranceM >= 0.0 ) || !( sampleSpacingPx >= 0.0 ) || !( newGapM >= 0.0 ) || majorityHalfWindow < 0 )
      throw std::invalid_argument( "the map's tolerance, the sample spacing, the new roads' gap and the majority window must not be negative" );
  }

  double RevisedPiece::lengthM() const
  {
    double length = 0.0;
    for ( size_t i = 1; i < course.size(); ++i )
      length += ( course[i] - course[i - 1] ).head<2>().norm();
    return length;
  }

  double MapRevisionSummary::lengthM( RevisionStatus status ) const
  {
    double length = 0.0;
    for ( const RevisedPiece &p : pieces )
      if ( p.status == status )
        length += p.lengthM();
    return length;
  }

  namespace
  {
    //! One place along a map road, as checked.
    struct Sample
    {
      Eigen::Vector3d ground = Eigen::Vector3d::Zero(); //!< on the mapped course, at the terrain
      Eigen::Vector2d inA = Eigen::Vector2d::Zero(), inB = Eigen::Vector2d::Zero();
      RevisionStatus status = RevisionStatus::Outside;
      Eigen::Vector2d foundA = Eigen::Vector2d::Zero(), foundB = Eigen::Vector2d::Zero(); //!< the band's centre, confirmed or moved
      double shiftM = 0.0;
      double offsetPx = 0.0, widthPx = 0.0; //!< confirmed or moved: the band's offset across the course in A and its width there
      //! Moved: every band off the course in A that B confirms (offset across the course in A, px; where; how far)
      struct Candidate
      {
        double offsetPx, widthPx;
        Eigen::Vector2d inA, inB;
        double shiftM;
      };
      std::vector<Candidate> candidates;
    };

    //! What the check needs of the pair.
    struct PairView
    {
      const GreyTiles &greyA, &greyB;
      const OrientedPairMapping &mapping;
      LineObjectOptions object;
      double groundPixelM = 0.0, tolerancePx = 0.0, shiftMaxPx = 0.0;
      double terrainSigmaM = 0.0; //!< of a height taken from the terrain
    };

    struct MeasuredVertex
    {
      Eigen::Vector3d point = Eigen::Vector3d::Zero(), sigmaM = Eigen::Vector3d::Zero();
      bool stereo = false;
    };

    bool inFrame( const OrientedImage &image, const Eigen::Vector3d &ground, Eigen::Vector2d &pixel, double marginPx )
    {
      const GroundProjection p = image.projectGroundToPixel( ground );
      pixel = p.pixelInImage;
      return p.ok() && pixel.x() > marginPx && pixel.y() > marginPx && pixel.x() < image.camera().width - marginPx && pixel.y() < image.camera().height - marginPx;
    }

    //! The bands across `along` at `at` within `searchPx` of it, nearest first (offsets along the normal of `along`).
    std::vector<CrossSection> bandsNear( const GreyTiles &grey, const Eigen::Vector2d &at, const Eigen::Vector2d &along, const LineObjectOptions &object, double searchPx )
    {
      const int half = static_cast<int>( std::ceil( searchPx + object.maxWidthPx ) ) + 6;
      const GreyWindow window = grey.around( at, half + 4 );
      const std::vector<double> profile = sampleCrossProfile( window.pixels, window.toWindow( at ), along, half, object.polarity, 1.5, 3 );
      std::vector<CrossSection> bands;
      for ( const CrossSection &s : findCrossSections( profile, object.minWidthPx, object.maxWidthPx, object.minContrast, object.maxVariation, false, object.polarity ) )
        if ( std::abs( s.offsetPx ) <= searchPx )
          bands.push_back( s );
      std::sort( bands.begin(), bands.end(), []( const CrossSection &x, const CrossSection &y ) { return std::abs( x.offsetPx ) < std::abs( y.offsetPx ); } );
      return bands;
    }

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

    Eigen::Vector2d directionAt( const std::vector<Sample> &samples, size_t i, bool inA )
    {
      const size_t from = i > 0 ? i - 1 : 0, to = std::min( i + 1, samples.size() - 1 );
      const Eigen::Vector2d d = inA ? samples[to].inA - samples[from].inA : samples[to].inB - samples[from].inB;
      return d.norm() > 1e-9 ? Eigen::Vector2d( d.normalized() ) : Eigen::Vector2d::UnitX();
    }

    /**
     * One sample's status: a band on the mapped course in both images
     * (confirmed); else the nearest band within the shift allowed in A whose
     * ground point shows a band in B (moved); else not found.
     */
    void check( Sample &s, const Eigen::Vector2d &alongA, const Eigen::Vector2d &alongB, const PairView &pair )
    {
      const std::vector<CrossSection> atA = bandsNear( pair.greyA, s.inA, alongA, pair.object, pair.tolerancePx );
      const std::vector<CrossSection> atB = bandsNear( pair.greyB, s.inB, alongB, pair.object, pair.tolerancePx );
      if ( !atA.empty() && !atB.empty() )
      {
        s.status = RevisionStatus::Confirmed;
        s.widthPx = atA.front().widthPx;
        s.offsetPx = atA.front().offsetPx;
        s.foundA = s.inA + atA.front().offsetPx * normalOf( alongA );
        s.foundB = s.inB + atB.front().offsetPx * normalOf( alongB );
        return;
      }
      s.status = RevisionStatus::NotFound;
      for ( const CrossSection &band : bandsNear( pair.greyA, s.inA, alongA, pair.object, pair.shiftMaxPx ) )
      {
        if ( std::abs( band.offsetPx ) - 0.5 * band.widthPx <= pair.tolerancePx )
          continue; // touching the course: the road itself, its kerb or shoulder (seen in A only), not a road moved
        const Eigen::Vector2d inA = s.inA + band.offsetPx * normalOf( alongA );
        const std::optional<Eigen::Vector3d> ground = pair.mapping.groundPoint( pair.mapping.imageA(), inA );
        if ( !ground )
          continue;
        Eigen::Vector2d inB;
        if ( !inFrame( pair.mapping.imageB(), *ground, inB, 2.0 ) )
          continue;
        const std::vector<CrossSection> there = bandsNear( pair.greyB, inB, alongB, pair.object, pair.tolerancePx );
        if ( !there.empty() )
          s.candidates.push_back( { band.offsetPx, band.widthPx, inA, inB + there.front().offsetPx * normalOf( alongB ), ( *ground - s.ground ).head<2>().norm() } );
      }
      if ( s.candidates.empty() )
        return;
      // the nearest for now; a moved stretch settles on the offset its samples share (settleShifts)
      s.status = RevisionStatus::Moved;
      s.foundA = s.candidates.front().inA;
      s.foundB = s.candidates.front().inB;
      s.shiftM = s.candidates.front().shiftM;
      s.offsetPx = s.candidates.front().offsetPx;
      s.widthPx = s.candidates.front().widthPx;
    }

    /**
     * A road moved as a whole: of a moved sample's bands (those in A that B
     * confirms), the one whose offset from the course the bands of the
     * neighbouring samples (5 either side) share most, within 1.5 px, and
     * at least 3 of them; a sample without such a band is not moved. The
     * moved road is found at about the same offset sample after sample; a
     * band of grass at any offset.
     */
    void settleShifts( std::vector<Sample> &samples )
    {
      std::vector<const Sample::Candidate *> chosen( samples.size(), nullptr );
      for ( size_t k = 0; k < samples.size(); ++k )
      {
        if ( samples[k].status != RevisionStatus::Moved )
          continue;
        // support from 5 samples either side; ties go to the support from 15 either side (a band along the
        // road for a few samples, a strip of field beside it, loses there), then to the band nearer the course
        const auto supportOf = [&]( const Sample::Candidate &c, size_t reach ) {
          int support = 0;
          for ( size_t j = k > reach ? k - reach : 0; j < std::min( samples.size(), k + reach + 1 ); ++j )
            if ( j != k && samples[j].status == RevisionStatus::Moved )
              for ( const Sample::Candidate &d : samples[j].candidates )
                if ( std::abs( d.offsetPx - c.offsetPx ) <= 1.5 )
                {
                  ++support;
                  break;
                }
          return support;
        };
        int bestSupport = 0, bestWide = 0;
        for ( const Sample::Candidate &c : samples[k].candidates )
        {
          const int support = supportOf( c, 5 ), wide = supportOf( c, 15 );
          if ( support > bestSupport || ( support == bestSupport && ( wide > bestWide || ( wide == bestWide && chosen[k] && std::abs( c.offsetPx ) < std::abs( chosen[k]->offsetPx ) ) ) ) )
          {
            bestSupport = support;
            bestWide = wide;
            chosen[k] = &c;
          }
        }
        if ( bestSupport < 3 )
          chosen[k] = nullptr;
      }
      for ( size_t k = 0; k < samples.size(); ++k )
      {
        Sample &s = samples[k];
        if ( s.status != RevisionStatus::Moved )
          continue;
        if ( !chosen[k] )
        {
          s.status = RevisionStatus::NotFound;
          continue;
        }
        s.foundA = chosen[k]->inA;
        s.foundB = chosen[k]->inB;
        s.shiftM = chosen[k]->shiftM;
        s.offsetPx = chosen[k]->offsetPx;
        s.widthPx = chosen[k]->widthPx;
      }
    }

    /**
     * A road runs on: a confirmed or moved sample counts only where a
     * sample of its status within 2 either side found its band in the first
     * image within 2 px of the same offset from the course and within 40 %
     * of the same width. Bands a
     * little brighter or darker than their sides, which grass with a coarse
     * grain holds everywhere, come at any offset and width from sample to
     * sample.
     */
    void requireContinuity( std::vector<Sample> &samples )
    {
      const auto continues = [&]( size_t k, size_t j ) {
        const Sample &s = samples[k], &t = samples[j];
        return t.status == s.status && std::abs( s.offsetPx - t.offsetPx ) <= 2.0 && std::abs( s.widthPx - t.widthPx ) <= 0.4 * std::max( s.widthPx, t.widthPx );
      };
      std::vector<size_t> isolated;
      for ( size_t k = 0; k < samples.size(); ++k )
        if ( samples[k].status == RevisionStatus::Confirmed || samples[k].status == RevisionStatus::Moved )
        {
          bool continued = false;
          for ( size_t j = k > 2 ? k - 2 : 0; j < std::min( samples.size(), k + 3 ) && !continued; ++j )
            continued = j != k && continues( k, j );
          if ( !continued )
            isolated.push_back( k );
        }
      for ( const size_t k : isolated )
        samples[k].status = RevisionStatus::NotFound;
    }

    //! Each sample's status replaced by the majority within `half` samples either side (ties keep their own).
    std::vector<RevisionStatus> majorityStatus( const std::vector<Sample> &samples, int half )
    {
      std::vector<RevisionStatus> out( samples.size() );
      for ( size_t i = 0; i < samples.size(); ++i )
      {
        std::map<RevisionStatus, int> votes;
        for ( size_t k = i > static_cast<size_t>( half ) ? i - half : 0; k < std::min( samples.size(), i + half + 1 ); ++k )
          ++votes[samples[k].status];
        RevisionStatus best = samples[i].status;
        for ( const auto &[status, count] : votes )
          if ( count > votes[best] )
            best = status;
        out[i] = best;
      }
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
          piece.course.push_back( samples[k].ground );
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
          for ( size_t k = from; k < to; ++k )
            if ( samples[k].status == piece.status )
            {
              const MeasuredVertex v = measured( samples[k], directionAt( samples, k, false ), pair );
              course.push_back( v.point );
              sigma.push_back( v.sigmaM );
              stereo.push_back( v.stereo );
            }
          if ( course.size() >= 2 )
          {
            piece.course = std::move( course );
            piece.sigmaM = std::move( sigma );
            piece.heightByStereo = std::move( stereo );
          }
        }
        if ( piece.course.size() >= 2 )
          out.push_back( std::move( piece ) );
        from = to;
      }
    }

    double distanceXY( const Eigen::Vector3d &p, const std::vector<Eigen::Vector3d> &line )
    {
      double best = std::numeric_limits<double>::infinity();
      for ( size_t i = 0; i + 1 < line.size(); ++i )
      {
        const Eigen::Vector2d a = line[i].head<2>(), ab = line[i + 1].head<2>() - a;
        const double t = ab.squaredNorm() > 0.0 ? std::clamp( ( p.head<2>() - a ).dot( ab ) / ab.squaredNorm(), 0.0, 1.0 ) : 0.0;
        best = std::min( best, ( a + t * ab - p.head<2>() ).norm() );
      }
      return best;
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
            explained = explained || distanceXY( v.point, *course ) <= gapM;
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

  MapRevisionSummary reviseRoads( std::shared_ptr<const RasterReader> readerA, std::shared_ptr<const RasterReader> readerB, const OrientedImage &a, const OrientedImage &b,
                                  const std::vector<MapRoad> &map, const MapRevisionOptions &options, const ExtractionProgress &progress )
  {
    using Range = std::optional<std::pair<double, double>>;
    const auto range = []( const RasterReader &r ) { return r.eightBit() ? Range() : Range( greyRangeOf( r ) ); };
    const Range rangeA = range( *readerA ), rangeB = range( *readerB );
    PairMatchWindows matching( matchWindowsOf( readerA, readerB, rangeA, rangeB ), readerA->size(), readerB->size() );
    return reviseRoads( greyTilesOf( readerA, rangeA ), greyTilesOf( readerB, rangeB ), matching, a, b, map, options, progress );
  }

  MapRevisionSummary reviseRoads( const MatchImage &imageA, const MatchImage &imageB, const OrientedImage &a, const OrientedImage &b, const std::vector<MapRoad> &map,
                                  const MapRevisionOptions &options, const ExtractionProgress &progress )
  {
    if ( imageA.empty() || imageB.empty() || imageA.windowed() || imageB.windowed() )
      throw std::invalid_argument( "map revision needs both images of the pair, whole" );
    PairMatchWindows matching( imageA, imageB );
    return reviseRoads( GreyTiles( imageA.grey() ), GreyTiles( imageB.grey() ), matching, a, b, map, options, progress );
  }

  MapRevisionSummary reviseRoads( const GreyTiles &greyA, const GreyTiles &greyB, PairMatchWindows &matching, const OrientedImage &a, const OrientedImage &b,
                                  const std::vector<MapRoad> &map, const MapRevisionOptions &options, const ExtractionProgress &progress )
  {
    options.check();
    MapRevisionSummary summary;
    // 1. the pair's own extraction: its terrain height, its widths in pixels and the roads it finds
    summary.extraction = extractRoadNetwork( greyA, greyB, matching, &a, &b, options.network, progress );
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
    const double spacingPx = options.sampleSpacingPx > 0.0 ? options.sampleSpacingPx : std::max( 4.0, pair.object.minWidthPx );

    // 2. each map road checked along its course, split where its status changes
    for ( size_t r = 0; r < map.size(); ++r )
    {
      if ( !validRoad( map[r] ) )
      {
        RevisedPiece invalid;
        invalid.road = r;
        invalid.status = RevisionStatus::InvalidGeometry;
        invalid.course = map[r].vertices;
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
        samples.push_back( s );
      }
      for ( size_t i = 0; i < samples.size(); ++i )
        if ( samples[i].status != RevisionStatus::Outside )
          check( samples[i], directionAt( samples, i, true ), directionAt( samples, i, false ), pair );
      settleShifts( samples );
      requireContinuity( samples );
      summary.samples += static_cast<int>( samples.size() );
      piecesOf( r, samples, majorityStatus( samples, options.majorityHalfWindow ), pair, summary.pieces );
    }

    // 3. the roads the extraction found that no map road explains
    const double gapM = options.newGapM > 0.0 ? options.newGapM : std::max( 3.0 * options.toleranceM, 10.0 * pair.groundPixelM );
    summary.newRoads = newRoads( summary.extraction.network, map, summary.pieces, gapM );
    return summary;
  }

} // namespace geostation
