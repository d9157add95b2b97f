/***************************************************************************
  localextraction.cpp - LEM, the local extraction method
 ***************************************************************************/
#include "extraction/localextraction.h"
#include "geometry/rotation.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace geostation
{

  std::string deadEndKindName( DeadEndKind kind )
  {
    switch ( kind )
    {
      case DeadEndKind::ImageBorder:
        return "image_border";
      case DeadEndKind::KnownRoad:
        return "known_road";
      case DeadEndKind::BreakOff:
        return "break_off";
      case DeadEndKind::FinalBreakOff:
        return "final_break_off";
      case DeadEndKind::Ideal:
        return "ideal";
      case DeadEndKind::Verification:
        return "verification";
      case DeadEndKind::Unverified:
        return "unverified";
      case DeadEndKind::SubImageBorder:
        return "sub_image_border";
    }
    return "unknown";
  }

  void LemOptions::check() const
  {
    if ( stepPx < 0.0 || searchPx < 0.0 )
      throw std::invalid_argument( "LEM's step and search range must not be negative (0: automatic)" );
    if ( !( maxTurnDeg > 0.0 && maxTurnDeg < 90.0 ) )
      throw std::invalid_argument( "LEM's direction change per step must be between 0 and 90 degrees" );
    if ( !( widthTolerance > 0.0 && widthTolerance < 1.0 ) )
      throw std::invalid_argument( "LEM's width tolerance must be between 0 and 1" );
    if ( !( contrastFraction > 0.0 && contrastFraction <= 1.0 ) )
      throw std::invalid_argument( "LEM's contrast fraction must be in (0, 1]" );
    if ( maxSteps < 1 )
      throw std::invalid_argument( "LEM needs at least one step" );
    if ( openSideWidths < 0.0 )
      throw std::invalid_argument( "LEM's reach through a junction's mouth must not be negative" );
  }

  double lemStepPx( const LemOptions &options, double widthPx )
  {
    return options.stepPx > 0.0 ? options.stepPx : std::clamp( widthPx, 4.0, 12.0 );
  }

  bool nearImageBorder( const cv::Mat &grey, const Eigen::Vector2d &pixelInImage, double widthPx )
  {
    return nearImageBorder( grey.size(), pixelInImage, widthPx );
  }

  bool nearImageBorder( const cv::Size &size, const Eigen::Vector2d &pixelInImage, double widthPx )
  {
    const double margin = 0.5 * widthPx + std::max( 2.0, 0.5 * widthPx ) + 3.0;
    return pixelInImage.x() < margin || pixelInImage.y() < margin || pixelInImage.x() > size.width - margin || pixelInImage.y() > size.height - margin;
  }

  std::optional<Eigen::Vector2d> knownLineAhead( const ResultMatrix &matrix, const Eigen::Vector2d &pixelInImage, const Eigen::Vector2d &behind,
                                                 const Eigen::Vector2d &direction, double radiusPx, double minAheadPx )
  {
    const int r = static_cast<int>( std::ceil( radiusPx ) );
    const int cc = static_cast<int>( std::floor( pixelInImage.x() ) ), rc = static_cast<int>( std::floor( pixelInImage.y() ) );
    std::optional<Eigen::Vector2d> best;
    double bestD2 = radiusPx * radiusPx;
    // (a view of the matrix may begin off its origin: at() is 0 outside what it holds)
    for ( int row = rc - r; row <= rc + r; ++row )
      for ( int col = cc - r; col <= cc + r; ++col )
      {
        if ( !matrix.at( col, row ) )
          continue;
        const Eigen::Vector2d cell( col + 0.5, row + 0.5 );
        if ( ( cell - behind ).dot( direction ) <= minAheadPx )
          continue;
        const double d2 = ( cell - pixelInImage ).squaredNorm();
        if ( d2 <= bestD2 )
        {
          bestD2 = d2;
          best = cell;
        }
      }
    return best;
  }

  std::optional<LineState> localStep( const cv::Mat &grey, const LineState &from, const LineObjectOptions &object, const LemOptions &options, bool openSide )
  {
    const double w = from.widthPx;
    const double step = lemStepPx( options, w );
    // through a junction's mouth the line keeps its course: the open side cannot steer it
    const double search = openSide ? 1.5 : ( options.searchPx > 0.0 ? options.searchPx : 0.35 * w + 1.5 );
    const double tolerance = openSide ? 0.1 : options.widthTolerance;
    const double wMax = std::min( object.maxWidthPx, w * ( 1.0 + tolerance ) );
    const double wMin = std::max( object.minWidthPx, w * ( 1.0 - tolerance ) );
    if ( wMin > wMax )
      return std::nullopt;
    const Eigen::Vector2d predicted = from.pixelInImage + step * from.direction;
    const int half = static_cast<int>( std::ceil( 0.5 * wMax + std::max( 2.0, 0.5 * wMax ) + 2.0 + search ) );
    const std::vector<double> profile = sampleCrossProfile( grey, predicted, from.direction, half, object.polarity, step / 3.0, 3 );
    const double minContrast = std::max( object.minContrast, options.contrastFraction * from.contrast );
    const std::vector<CrossSection> sections = findCrossSections( profile, wMin, wMax, minContrast, object.maxVariation, openSide, object.polarity );
    const CrossSection *chosen = nullptr;
    for ( const CrossSection &s : sections )
      if ( std::abs( s.offsetPx ) <= search && ( from.tone == 0 || s.tone != -from.tone ) && ( !chosen || std::abs( s.offsetPx ) < std::abs( chosen->offsetPx ) ) )
        chosen = &s;
    if ( !chosen )
      return std::nullopt;
    const Eigen::Vector2d found = predicted + chosen->offsetPx * normalOf( from.direction );
    const Eigen::Vector2d heading = ( found - from.pixelInImage ).normalized();
    if ( heading.dot( from.direction ) < std::cos( options.maxTurnDeg * kPi / 180.0 ) )
      return std::nullopt;
    LineState next;
    next.pixelInImage = found;
    next.direction = openSide ? from.direction : Eigen::Vector2d( ( from.direction + heading ).normalized() );
    next.widthPx = openSide ? w : 0.8 * w + 0.2 * chosen->widthPx;
    next.contrast = openSide ? from.contrast : 0.8 * from.contrast + 0.2 * chosen->contrast;
    next.tone = openSide ? from.tone : chosen->tone;
    return next;
  }

  LemSummary followLocally( const cv::Mat &grey, const ResultMatrix &matrix, const LineState &start, const LineObjectOptions &object,
                            const LemOptions &options )
  {
    LemSummary summary;
    summary.pixels.push_back( start.pixelInImage );
    summary.end = start;
    double openStepsPx = 0.0;
    while ( summary.steps < options.maxSteps )
    {
      if ( nearImageBorder( grey, summary.end.pixelInImage + lemStepPx( options, summary.end.widthPx ) * summary.end.direction, summary.end.widthPx ) )
      {
        summary.stop = DeadEndKind::ImageBorder;
        return summary;
      }
      std::optional<LineState> next = localStep( grey, summary.end, object, options );
      if ( next )
        openStepsPx = 0.0;
      else if ( summary.steps >= 2 && openStepsPx < options.openSideWidths * summary.end.widthPx )
      {
        // a junction's mouth: the band opens on one side
        next = localStep( grey, summary.end, object, options, true );
        if ( next )
          openStepsPx += ( next->pixelInImage - summary.end.pixelInImage ).norm();
      }
      if ( !next )
      {
        summary.stop = DeadEndKind::BreakOff;
        return summary;
      }
      const double step = ( next->pixelInImage - summary.end.pixelInImage ).norm();
      if ( const std::optional<Eigen::Vector2d> known = knownLineAhead( matrix, next->pixelInImage, summary.end.pixelInImage, summary.end.direction,
                                                                        next->widthPx + 2.0, 0.5 * step ) )
      {
        summary.pixels.push_back( *known );
        summary.end.pixelInImage = *known;
        summary.stop = DeadEndKind::KnownRoad;
        ++summary.steps;
        return summary;
      }
      summary.pixels.push_back( next->pixelInImage );
      summary.end = *next;
      ++summary.steps;
    }
    summary.stop = DeadEndKind::BreakOff;
    return summary;
  }

} // namespace geostation
