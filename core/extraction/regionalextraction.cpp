/***************************************************************************
  regionalextraction.cpp - REM, the regional extraction method
 ***************************************************************************/
#include "extraction/regionalextraction.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace geostation
{

  void RemOptions::check() const
  {
    if ( areaLengthPx < 0.0 || areaHalfWidthPx < 0.0 || spacingPx < 0.0 )
      throw std::invalid_argument( "REM's area size and line spacing must not be negative (0: automatic)" );
    if ( !( semiThreshold > 0.0 && semiThreshold < 1.5 ) || !( confirmThreshold > 0.0 && confirmThreshold < 1.5 ) )
      throw std::invalid_argument( "REM's thresholds must lie between 0 and 1.5 (confidence)" );
    if ( candidatesPerLine < 1 || relaxationIterations < 0 || maxGapPx < 0.0 || maxAreas < 1 )
      throw std::invalid_argument( "REM needs at least one candidate per line and one area, and non-negative iterations and gaps" );
    if ( !( maxAngleDeg > 0.0 && maxAngleDeg < 80.0 ) )
      throw std::invalid_argument( "REM's angle limit must be between 0 and 80 degrees" );
  }

  AreaOfInterest RemOptions::areaAhead( const LineState &state ) const
  {
    AreaOfInterest area;
    area.origin = state.pixelInImage;
    area.axis = state.direction;
    area.lengthPx = areaLengthPx > 0.0 ? areaLengthPx : std::max( 40.0, 5.0 * state.widthPx );
    area.halfWidthPx = areaHalfWidthPx > 0.0 ? areaHalfWidthPx : std::max( 6.0, 0.75 * state.widthPx );
    area.spacingPx = spacingPx > 0.0 ? spacingPx : std::clamp( state.widthPx / 3.0, 2.0, 4.0 );
    return area;
  }

  AreaAnalysisOptions RemOptions::analysis( const LineState &state, int polarity ) const
  {
    AreaAnalysisOptions a;
    a.polarity = polarity;
    a.widthPx = state.widthPx;
    a.contrast = state.contrast;
    a.semiThreshold = semiThreshold;
    a.candidatesPerLine = candidatesPerLine;
    a.relaxationIterations = relaxationIterations;
    a.confirmThreshold = confirmThreshold;
    a.maxAngleDeg = maxAngleDeg;
    const AreaOfInterest area = areaAhead( state );
    a.maxGapLines = static_cast<int>( std::ceil( ( maxGapPx > 0.0 ? maxGapPx : 2.0 * state.widthPx ) / area.spacingPx ) );
    return a;
  }

  std::optional<CrossSection> refineAcross( const cv::Mat &grey, const Eigen::Vector2d &pixelInImage, const Eigen::Vector2d &direction, double widthPx,
                                            const LineObjectOptions &object, double searchPx )
  {
    const double wMin = std::max( 2.0, 0.6 * widthPx ), wMax = std::max( wMin, 1.6 * widthPx );
    const int half = static_cast<int>( std::ceil( 0.5 * wMax + std::max( 2.0, 0.5 * wMax ) + 2.0 + searchPx ) );
    const std::vector<double> profile = sampleCrossProfile( grey, pixelInImage, direction, half, object.polarity, 1.5, 3 );
    std::optional<CrossSection> best;
    for ( const CrossSection &s : findCrossSections( profile, wMin, wMax, 0.5 * object.minContrast, 2.0 * object.maxVariation, false, object.polarity ) )
      if ( std::abs( s.offsetPx ) <= searchPx && ( !best || std::abs( s.offsetPx ) < std::abs( best->offsetPx ) ) )
        best = s;
    return best;
  }

  RemSummary followRegionally( const cv::Mat &grey, const ResultMatrix &matrix, const LineState &start, const LineObjectOptions &object,
                               const LemOptions &lem, const RemOptions &options )
  {
    RemSummary summary;
    summary.pixels.push_back( start.pixelInImage );
    summary.end = start;
    while ( summary.areas < options.maxAreas )
    {
      const AreaOfInterest area = options.areaAhead( summary.end );
      if ( nearImageBorder( grey, summary.end.pixelInImage + area.spacingPx * area.axis, summary.end.widthPx ) )
      {
        summary.stop = DeadEndKind::ImageBorder;
        return summary;
      }
      const AreaAnalysisOptions analysis = options.analysis( summary.end, object.polarity );
      const std::vector<std::vector<AreaCandidate>> lines = analyseArea( grey, area, analysis, 0.0 );
      const std::vector<ChainLink> chain = bestChain( lines, area, analysis, 0.0 );
      double meanConfidence = 0.0;
      for ( const ChainLink &link : chain )
        meanConfidence += link.confidence / chain.size();
      if ( chain.size() < 2 || meanConfidence < options.minChainConfidence )
      {
        summary.stop = DeadEndKind::FinalBreakOff;
        return summary;
      }
      ++summary.areas;
      Eigen::Vector2d previous = summary.end.pixelInImage;
      const size_t firstNew = summary.pixels.size();
      for ( const ChainLink &link : chain )
      {
        Eigen::Vector2d p = area.pointOn( link.line, link.offsetPx );
        if ( nearImageBorder( grey, p, summary.end.widthPx ) )
        {
          summary.end.pixelInImage = previous;
          summary.stop = DeadEndKind::ImageBorder;
          return summary;
        }
        if ( const std::optional<CrossSection> refined = refineAcross( grey, p, area.axis, summary.end.widthPx, object, 2.0 ) )
          p += refined->offsetPx * normalOf( area.axis );
        if ( const std::optional<Eigen::Vector2d> known = knownLineAhead( matrix, p, previous, area.axis, summary.end.widthPx + 2.0, 0.5 * area.spacingPx ) )
        {
          summary.pixels.push_back( *known );
          summary.end.pixelInImage = *known;
          summary.stop = DeadEndKind::KnownRoad;
          return summary;
        }
        summary.pixels.push_back( p );
        previous = p;
      }
      // the new direction from the chain's last stretch (about two widths)
      const Eigen::Vector2d last = summary.pixels.back();
      Eigen::Vector2d back = summary.pixels[firstNew - 1];
      for ( size_t k = summary.pixels.size(); k-- > firstNew; )
        if ( ( last - summary.pixels[k] ).norm() >= std::max( 10.0, 2.0 * summary.end.widthPx ) )
        {
          back = summary.pixels[k];
          break;
        }
      if ( ( last - back ).norm() > 1.0 )
        summary.end.direction = ( last - back ).normalized();
      summary.end.pixelInImage = last;
      if ( chain.back().line < area.lineCount() - 1 - analysis.maxGapLines )
      {
        summary.stop = DeadEndKind::FinalBreakOff; // the line ends inside the area
        return summary;
      }
      // ideal again: two LEM steps comply
      if ( const std::optional<LineState> one = localStep( grey, summary.end, object, lem ) )
        if ( localStep( grey, *one, object, lem ) )
        {
          summary.stop = DeadEndKind::Ideal;
          return summary;
        }
    }
    summary.stop = DeadEndKind::FinalBreakOff;
    return summary;
  }

} // namespace geostation
