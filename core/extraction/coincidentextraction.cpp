/***************************************************************************
  coincidentextraction.cpp - lines extracted in a stereo pair, each
  verified in the partner
 ***************************************************************************/
#include "extraction/coincidentextraction.h"
#include "extraction/stopwatch.h"
#include "geometry/polyline.h"
#include "geometry/rotation.h"

#include "extraction/centrerefinement.h"
#include "extraction/regionalextraction.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace geostation
{

  void CoincidentExtractionOptions::check() const
  {
    extraction.check();
    verification.check();
    borders.check();
    companions.check();
    if ( maxRounds < 1 || maxRounds > 20 )
      throw std::invalid_argument( "the number of extraction rounds must be 1 to 20" );
    if ( !( minRoundGain >= 0.0 && minRoundGain < 1.0 ) )
      throw std::invalid_argument( "the minimum gain of a round must be a fraction in [0, 1)" );
    if ( !( minBandSupport >= 0.0 && minBandSupport <= 1.0 ) )
      throw std::invalid_argument( "the band support a final line needs must be a fraction in [0, 1]" );
    if ( !( maxBandWidening == 0.0 || maxBandWidening > 1.0 ) )
      throw std::invalid_argument( "the widening of a final line's band must be 0 (any) or more than 1" );
    if ( kiteLengthPx < 0.0 || kiteWidthPx < 0.0 )
      throw std::invalid_argument( "the intersection search area must not have a negative size (0: automatic)" );
  }

  namespace
  {
    /**
     * `lines` without those the band does not carry (bandSupport() below `minSupport`): a chain through the
     * grain of a field or a row of trees shows a band only here and there; nor those along which the band
     * widens steadily by `maxWidening` or more (a strip of field converging on a road). An end at a junction
     * is judged beyond the junction's mouth (its profiles cross the other road). Every line stays where the
     * roads are lines, at most 4 px wide (one profile across a 2 px street among blocks tells little).
     * `removed` counts the others.
     */
    std::vector<CompiledPolygon> bandSupportedLines( const GreyTiles &grey, const std::vector<CompiledPolygon> &lines, const LineObjectOptions &object,
                                                     double minSupport, double maxWidening, int &removed )
    {
      if ( ( minSupport <= 0.0 && maxWidening <= 0.0 ) || object.maxWidthPx <= 4.0 )
        return lines;
      if ( maxWidening <= 0.0 )
        maxWidening = std::numeric_limits<double>::infinity();
      std::vector<CompiledPolygon> kept;
      for ( const CompiledPolygon &line : lines )
      {
        const BandSupport band = bandSupport( grey, line.pixels, object, line.startEnd == PolygonEnd::Intersection, line.endEnd == PolygonEnd::Intersection );
        if ( band.share >= minSupport && band.widening < maxWidening )
          kept.push_back( line );
        else
          ++removed;
      }
      return kept;
    }

    void add( StageCounts &to, const StageCounts &from )
    {
      to.seconds += from.seconds;
      to.linePx += from.linePx;
      to.imagePixels += from.imagePixels;
    }

    std::vector<DeadEnd> openEnds( const std::vector<CompiledPolygon> &polygons )
    {
      std::vector<DeadEnd> ends;
      for ( const CompiledPolygon &p : polygons )
      {
        if ( p.pixels.size() < 2 )
          continue;
        for ( const bool atStart : { true, false } )
        {
          if ( ( atStart ? p.startEnd : p.endEnd ) != PolygonEnd::DeadEnd )
            continue;
          const Eigen::Vector2d end = atStart ? p.pixels.front() : p.pixels.back();
          const size_t k = std::min<size_t>( 5, p.pixels.size() - 1 );
          const Eigen::Vector2d inner = atStart ? p.pixels[k] : p.pixels[p.pixels.size() - 1 - k];
          DeadEnd d;
          d.state.pixelInImage = end;
          d.state.direction = ( end - inner ).norm() > 0 ? Eigen::Vector2d( ( end - inner ).normalized() ) : Eigen::Vector2d::UnitX();
          d.kind = DeadEndKind::FinalBreakOff;
          ends.push_back( d );
        }
      }
      return ends;
    }
  } // namespace

  int bridgeOpenEnds( ResultMatrix &matrix, const std::string &symbols, uint8_t symbol, double kiteLengthPx, double kiteWidthPx )
  {
    const CompilationSummary compiled = compileMaxLengthPolygons( matrix, symbols, false, 1 );
    int joins = 0;
    for ( const CompiledPolygon &polygon : compiled.polygons )
    {
      if ( polygon.pixels.size() < 2 )
        continue;
      for ( const bool atStart : { true, false } )
      {
        if ( ( atStart ? polygon.startEnd : polygon.endEnd ) != PolygonEnd::DeadEnd )
          continue;
        const Eigen::Vector2d q = atStart ? polygon.pixels.front() : polygon.pixels.back();
        const size_t k = std::min<size_t>( 5, polygon.pixels.size() - 1 );
        const Eigen::Vector2d inner = atStart ? polygon.pixels[k] : polygon.pixels[polygon.pixels.size() - 1 - k];
        if ( ( q - inner ).norm() < 1.0 )
          continue;
        const Eigen::Vector2d axis = ( q - inner ).normalized(), normal( -axis.y(), axis.x() );
        // the kite: widest (kiteWidth) at 30 % of its length, pointed at both ends
        const double widest = 0.3 * kiteLengthPx;
        std::optional<Eigen::Vector2d> best;
        double bestDistance = std::numeric_limits<double>::infinity();
        const int reach = static_cast<int>( std::ceil( kiteLengthPx ) );
        for ( int dr = -reach; dr <= reach; ++dr )
          for ( int dc = -reach; dc <= reach; ++dc )
          {
            const Eigen::Vector2d cell( std::floor( q.x() ) + dc + 0.5, std::floor( q.y() ) + dr + 0.5 );
            const uint8_t v = matrix.at( static_cast<int>( std::floor( cell.x() ) ), static_cast<int>( std::floor( cell.y() ) ) );
            if ( !v || symbols.find( static_cast<char>( v ) ) == std::string::npos )
              continue;
            const double t = ( cell - q ).dot( axis ), s = std::abs( ( cell - q ).dot( normal ) );
            if ( t <= 0.5 || t > kiteLengthPx )
              continue;
            const double half = 0.5 * kiteWidthPx * ( t <= widest ? t / widest : ( kiteLengthPx - t ) / ( kiteLengthPx - widest ) );
            if ( s > half + 0.5 )
              continue;
            // the search favours the main axis (§4.4.3): a line is continued along its course, not to the nearest pixel aside
            const double distance = t + 3.0 * s;
            if ( distance >= bestDistance || nearestOnPolyline( polygon.pixels, cell ).distance < 2.0 )
              continue;
            bestDistance = distance;
            best = cell;
          }
        if ( best )
        {
          matrix.drawPolyline( { q, *best }, symbol );
          ++joins;
        }
      }
    }
    return joins;
  }

  int bridgeFacingEnds( ResultMatrix &matrix, const GreyTiles &image, const std::string &symbols, uint8_t symbol, const LineObjectOptions &object, double maxDistancePx )
  {
    const CompilationSummary compiled = compileMaxLengthPolygons( matrix, symbols, false, 1 );
    const std::vector<DeadEnd> ends = openEnds( compiled.polygons );
    std::vector<bool> used( ends.size(), false );
    const double cosLimit = std::cos( degToRad( 25.0 ) );
    int joins = 0;
    for ( size_t i = 0; i < ends.size(); ++i )
    {
      if ( used[i] )
        continue;
      std::optional<size_t> best;
      std::vector<Eigen::Vector2d> bestPath; //!< the join along the band's centre
      double bestDistance = maxDistancePx;
      for ( size_t k = 0; k < ends.size(); ++k )
      {
        if ( k == i || used[k] )
          continue;
        const Eigen::Vector2d d = ends[k].state.pixelInImage - ends[i].state.pixelInImage;
        const double distance = d.norm();
        if ( distance < 1.0 || distance >= bestDistance )
          continue;
        if ( ends[i].state.direction.dot( d ) < cosLimit * distance || ends[k].state.direction.dot( -d ) < cosLimit * distance )
          continue;
        // nothing extracted along the line between them (the join would cross another line)
        const Eigen::Vector2d axis = d / distance, normal = normalOf( axis );
        bool crosses = false;
        for ( double t = 3.0; t < distance - 3.0 && !crosses; t += 1.0 )
          crosses = matrix.nearestSymbol( ends[i].state.pixelInImage + t * axis, 1.0 ).has_value();
        if ( crosses )
          continue;
        // the pixels between the ends: the band's offset (at most 15 % of the way) and a profile of 3 widths across
        const GreyWindow window = image.covering( ends[i].state.pixelInImage, ends[k].state.pixelInImage,
                                                  static_cast<int>( std::ceil( 0.15 * distance + 3.0 * object.maxWidthPx ) ) + 24 );
        const cv::Mat &grey = window.pixels;
        const Eigen::Vector2d p0 = window.toWindow( ends[i].state.pixelInImage );
        const std::optional<CrossSection> atEnd = refineAcross( grey, p0 - 4.0 * axis, axis, 0.5 * ( object.minWidthPx + object.maxWidthPx ), object, 3.0 );
        const double width = atEnd ? atEnd->widthPx : 0.5 * ( object.minWidthPx + object.maxWidthPx );
        const int half = static_cast<int>( std::ceil( width ) ) + 6;
        // the band, followed from this end: its centre's offset across the line between the ends is tracked (a
        // curved road leaves the chord), within what the ends' courses allow
        const double maxOffset = std::max( 2.5, 0.15 * distance );
        constexpr double kStepPx = 2.0;
        int samples = 0, supported = 0, gap = 0, longestGap = 0;
        double offset = 0.0;
        std::vector<Eigen::Vector2d> centres { p0 };
        for ( double t = kStepPx; t < distance - 1.0; t += kStepPx, ++samples )
        {
          const Eigen::Vector2d at = p0 + t * axis + offset * normal;
          const std::vector<double> profile = sampleCrossProfile( grey, at, axis, half, object.polarity, 1.0, 3 );
          std::optional<double> shift;
          for ( const CrossSection &c : findCrossSections( profile, 0.8 * width, 1.2 * width, 0.5 * object.minContrast, 2.0 * object.maxVariation, true, object.polarity ) )
            if ( std::abs( c.offsetPx ) <= 2.5 && std::abs( offset + c.offsetPx ) <= maxOffset && ( !shift || std::abs( c.offsetPx ) < std::abs( *shift ) ) )
              shift = c.offsetPx;
          if ( shift )
          {
            offset += *shift;
            centres.push_back( at + *shift * normal );
          }
          supported += shift.has_value();
          gap = shift ? 0 : gap + 1;
          longestGap = std::max( longestGap, gap );
        }
        // the band along 70 % of the way (a long stretch with one side in shadow), or along most of it with only
        // short interruptions - a tree's shadow across the road, a junction's mouth: at most three widths - where a
        // false join across a field finds the band rarely and loses it for long stretches
        const bool mostly = supported >= 0.7 * samples, brieflyInterrupted = supported >= 0.55 * samples && longestGap * kStepPx <= 3.0 * width;
        // and the band followed from this end arrives at the other one (not beside it: a shadow strip or a verge
        // alongside a road that is already there)
        const bool arrives = std::abs( offset ) <= 0.5 * width;
        if ( samples == 0 || !( mostly || brieflyInterrupted ) || !arrives )
          continue;
        centres.push_back( window.toWindow( ends[k].state.pixelInImage ) );
        for ( Eigen::Vector2d &c : centres )
          c = window.toImage( c );
        // and the band is not a line already there: a join along the road beside a line that wanders off the chord
        // would draw the road twice
        const double clear = std::max( 2.0, 0.5 * width );
        bool alongside = false;
        for ( const Eigen::Vector2d &c : densifyPolyline( centres, 1.0 ) )
          if ( ( c - centres.front() ).norm() > clear + 2.0 && ( c - centres.back() ).norm() > clear + 2.0 && matrix.nearestSymbol( c, clear ) )
          {
            alongside = true;
            break;
          }
        if ( alongside )
          continue;
        bestDistance = distance;
        best = k;
        bestPath = centres;
      }
      if ( best )
      {
        matrix.drawPolyline( bestPath, symbol );
        used[i] = used[*best] = true;
        ++joins;
      }
    }
    return joins;
  }

  int pruneSpurs( ResultMatrix &matrix, const std::string &symbols, double maxLengthPx )
  {
    int removed = 0;
    for ( const CompiledPolygon &p : compileMaxLengthPolygons( matrix, symbols, false, 1 ).polygons )
    {
      const bool spur = ( p.startEnd == PolygonEnd::Intersection ) != ( p.endEnd == PolygonEnd::Intersection );
      const double length = polylineLength( p.pixels );
      if ( !spur || length >= maxLengthPx || p.pixels.size() < 2 )
        continue;
      // erase from the dead end to 2.5 px short of the intersection, three pixels wide (the staircase around the simplified line)
      std::vector<Eigen::Vector2d> line = p.pixels;
      if ( p.startEnd == PolygonEnd::Intersection )
        std::reverse( line.begin(), line.end() );
      const double keep = 2.5;
      std::vector<Eigen::Vector2d> cut { line.front() };
      double travelled = 0.0;
      for ( size_t i = 1; i < line.size(); ++i )
      {
        const double step = ( line[i] - line[i - 1] ).norm();
        if ( travelled + step > length - keep )
        {
          const double t = std::max( 0.0, ( length - keep - travelled ) / step );
          cut.push_back( line[i - 1] + t * ( line[i] - line[i - 1] ) );
          break;
        }
        travelled += step;
        cut.push_back( line[i] );
      }
      for ( const Eigen::Vector2d &offset : { Eigen::Vector2d( 0, 0 ), Eigen::Vector2d( 1, 0 ), Eigen::Vector2d( -1, 0 ), Eigen::Vector2d( 0, 1 ), Eigen::Vector2d( 0, -1 ) } )
      {
        std::vector<Eigen::Vector2d> shifted;
        for ( const Eigen::Vector2d &v : cut )
          shifted.push_back( v + offset );
        matrix.drawPolyline( shifted, 0, true );
      }
      ++removed;
    }
    return removed;
  }

  CoincidentExtractionSummary extractCoincident( const cv::Mat &greyA, const cv::Mat &greyB, const PairMapping &mapping,
                                                 const CoincidentExtractionOptions &options, const Progress &progress )
  {
    if ( greyA.empty() || greyB.empty() || greyA.type() != CV_8UC1 || greyB.type() != CV_8UC1 )
      throw std::invalid_argument( "coincident extraction needs two 8-bit single-band images" );
    return extractCoincident( GreyTiles( greyA ), GreyTiles( greyB ), mapping, options, progress );
  }

  CoincidentExtractionSummary extractCoincident( const GreyTiles &greyA, const GreyTiles &greyB, const PairMapping &mapping,
                                                 const CoincidentExtractionOptions &options, const Progress &progress )
  {
    options.check();
    CoincidentExtractionSummary summary;
    ResultMatrix matrix[2] = { ResultMatrix( greyA.width(), greyA.height() ), ResultMatrix( greyB.width(), greyB.height() ) };
    const GreyTiles *grey[2] = { &greyA, &greyB };
    const PixelMap toOther[2] = { [&]( const Eigen::Vector2d &p ) { return mapping.toB( p ); }, [&]( const Eigen::Vector2d &p ) { return mapping.toA( p ); } };
    std::vector<DeadEnd> continueFrom[2];
    bool searched[2] = { false, false };
    double totalAccepted = 0.0;

    for ( int round = 0; round < ( options.verify ? options.maxRounds : 1 ); ++round )
    {
      const int s = round % 2, t = 1 - s; // extract in s, verify in t
      const Stopwatch roundStart;
      RoundReport report;
      report.round = round + 1;
      report.image = s == 0 ? "A" : "B";
      const Progress roundProgress = progress.part( std::min( 1.0, round / static_cast<double>( options.maxRounds ) ), std::min( 1.0, ( round + 0.8 ) / options.maxRounds ) );
      const LineExtractionSummary extracted = extractLines( *grey[s], matrix[s], continueFrom[s], !searched[s], options.extraction, roundProgress );
      if ( extracted.cancelled )
      {
        summary = CoincidentExtractionSummary();
        summary.cancelled = true;
        return summary;
      }
      searched[s] = true;
      continueFrom[s].clear();
      add( summary.startStage, extracted.startStage );
      add( summary.lemStage, extracted.lemStage );
      add( summary.remStage, extracted.remStage );
      summary.subImages += extracted.subImages;
      summary.temporaryDeadEnds += extracted.temporaryDeadEnds;
      report.startingPoints = extracted.startingPoints;
      report.linesStarted = extracted.linesStarted;
      report.continued = extracted.continued;
      report.extractedPx = extracted.linePx;
      if ( !options.verify )
      {
        summary.rounds.push_back( report );
        break;
      }
      Stopwatch t0;
      const CompilationSummary compiled = compileMaxLengthPolygons( matrix[s], "S*+", true );
      summary.compilationStage.seconds += t0.seconds();
      report.polygons = static_cast<int>( compiled.polygons.size() );
      const VerificationSummary verified = verifyPolygons( *grey[s], *grey[t], compiled.polygons, toOther[s], options.extraction.object, options.verification );
      summary.verificationStage.seconds += verified.seconds;
      summary.verificationStage.linePx += verified.sourceLengthPx;
      report.wholly = verified.wholly;
      report.partly = verified.partly;
      report.rejected = verified.rejected;
      report.acceptedPx = verified.acceptedSourceLengthPx;
      for ( const VerifiedPart &part : verified.accepted )
      {
        matrix[t].drawPolyline( part.inTarget, ResultMatrix::kExternal );
        matrix[s].drawPolyline( part.inSource, ResultMatrix::kInternal );
      }
      continueFrom[t] = verified.continueFrom;
      report.seconds = roundStart.seconds();
      summary.rounds.push_back( report );
      totalAccepted += verified.acceptedSourceLengthPx;
      if ( !progress.report( std::min( 1.0, ( round + 1.0 ) / options.maxRounds ), "round " + std::to_string( round + 1 ) + " verified" ) )
      {
        summary = CoincidentExtractionSummary();
        summary.cancelled = true;
        return summary;
      }
      // a round after the first two that adds little ends the alternation (both images have had their starting points)
      if ( round >= 1 && verified.acceptedSourceLengthPx < options.minRoundGain * totalAccepted )
        break;
      if ( round >= 1 && continueFrom[t].empty() )
        break;
    }

    // final processing: bridge small gaps and broken intersections, compile
    const Stopwatch t0;
    const std::string finalSymbols = options.verify ? "IE" : "S*+";
    const double widest = options.extraction.object.maxWidthPx;
    const double kiteLength = options.kiteLengthPx > 0.0 ? options.kiteLengthPx : std::max( 20.0, 2.0 * widest );
    const double kiteWidth = options.kiteWidthPx > 0.0 ? options.kiteWidthPx : std::max( 12.0, widest );
    for ( int i = 0; i < 2; ++i )
    {
      // long gaps (a stretch in shadow) between ends that face each other, where the image shows the road between them
      summary.bridged += bridgeFacingEnds( matrix[i], *grey[i], finalSymbols, options.verify ? ResultMatrix::kInternal : ResultMatrix::kRegional,
                                           options.extraction.object, 12.0 * widest );
      for ( int pass = 0; pass < 3; ++pass ) // a gap closed in one pass gives an end nearby its line in the next
      {
        const int joins = bridgeOpenEnds( matrix[i], finalSymbols, options.verify ? ResultMatrix::kInternal : ResultMatrix::kRegional, kiteLength, kiteWidth );
        summary.bridged += joins;
        if ( joins == 0 )
          break;
      }
      for ( int pass = 0; pass < 3; ++pass ) // pruning can leave a new spur behind
      {
        const int removed = pruneSpurs( matrix[i], finalSymbols, kiteLength );
        summary.pruned += removed;
        if ( removed == 0 )
          break;
      }
    }
    CompilationSummary finalA = compileMaxLengthPolygons( matrix[0], finalSymbols, false );
    CompilationSummary finalB = compileMaxLengthPolygons( matrix[1], finalSymbols, false );
    // the lines moved from the pixel staircase onto their band's centre
    // (and the intersections to where their branches, moved, cross)
    const CentreRefinementSummary refinedA = refineLineCentres( *grey[0], finalA.polygons, options.extraction.object );
    const CentreRefinementSummary refinedB = refineLineCentres( *grey[1], finalB.polygons, options.extraction.object );
    // a road is one band: the markings, kerbs and shoulders found beside it go
    const CompanionLineSummary keptA = removeCompanionLines( *grey[0], refinedA.lines, options.extraction.object, options.companions );
    const CompanionLineSummary keptB = removeCompanionLines( *grey[1], refinedB.lines, options.extraction.object, options.companions );
    summary.companionsRemoved = keptA.removed + keptB.removed;
    // a line along a road's border (a shoulder, a kerb) where the road itself was not found goes onto the road
    const RoadBorderSummary onRoadA = moveBordersOntoRoads( *grey[0], keptA.lines, options.extraction.object, options.borders );
    const RoadBorderSummary onRoadB = moveBordersOntoRoads( *grey[1], keptB.lines, options.extraction.object, options.borders );
    summary.bordersMoved = onRoadA.moved + onRoadB.moved;
    // a line the band does not carry along most of its course goes (a chain through the grain of a field)
    summary.linesA = bandSupportedLines( *grey[0], onRoadA.lines, options.extraction.object, options.minBandSupport, options.maxBandWidening, summary.unsupportedRemoved );
    summary.linesB = bandSupportedLines( *grey[1], onRoadB.lines, options.extraction.object, options.minBandSupport, options.maxBandWidening, summary.unsupportedRemoved );
    summary.compilationStage.seconds += t0.seconds();
    summary.intersectionsA = refinedA.movedIntersections( finalA.intersections );
    summary.intersectionsB = refinedB.movedIntersections( finalB.intersections );
    summary.deadEndsA = openEnds( summary.linesA );
    summary.deadEndsB = openEnds( summary.linesB );
    progress.report( 1.0 );
    return summary;
  }

} // namespace geostation

