/***************************************************************************
  startingpoints.cpp - starting points on sample rows and columns
 ***************************************************************************/
#include "extraction/startingpoints.h"
#include "geometry/rotation.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace geostation
{

  namespace
  {
    //! Mean grey (polarity applied) along a segment of `length` through `centre`, 2 px apart, and its standard deviation.
    std::pair<double, double> meanAlong( const cv::Mat &grey, const Eigen::Vector2d &centre, const Eigen::Vector2d &direction, double length, int polarity )
    {
      double sum = 0.0, sumSq = 0.0;
      int n = 0;
      for ( double t = -0.5 * length; t <= 0.5 * length; t += 2.0 )
      {
        const Eigen::Vector2d p = centre + t * direction;
        const double v = greyAt( grey, p.x(), p.y() );
        if ( std::isnan( v ) )
          continue;
        sum += profileSign( polarity ) * v;
        sumSq += v * v;
        ++n;
      }
      if ( n == 0 )
        return { std::nan( "" ), 0.0 };
      const double mean = sum / n;
      return { mean, std::sqrt( std::max( 0.0, sumSq / n - mean * mean ) ) };
    }

    //! The nearest complying band across `direction` at `centre`, within `searchPx`.
    std::optional<CrossSection> bandAcross( const cv::Mat &grey, const Eigen::Vector2d &centre, const Eigen::Vector2d &direction, const LineObjectOptions &object, double searchPx )
    {
      const int half = static_cast<int>( std::ceil( 0.5 * object.maxWidthPx + std::max( 2.0, 0.5 * object.maxWidthPx ) + 2.0 + searchPx ) );
      const std::vector<double> profile = sampleCrossProfile( grey, centre, direction, half, object.polarity, 2.0, 3 );
      std::optional<CrossSection> best;
      for ( const CrossSection &s : findCrossSections( profile, object.minWidthPx, object.maxWidthPx, object.minContrast, object.maxVariation, false, object.polarity ) )
        if ( std::abs( s.offsetPx ) <= searchPx && ( !best || std::abs( s.offsetPx ) < std::abs( best->offsetPx ) ) )
          best = s;
      return best;
    }

    double meanWidthOf( const std::optional<CrossSection> &a, const std::optional<CrossSection> &b, const std::optional<CrossSection> &c )
    {
      return ( a->widthPx + b->widthPx + c->widthPx ) / 3.0;
    }

    //! The full test of a candidate; the starting point or nothing.
    std::optional<LineState> testCandidate( const cv::Mat &grey, const Eigen::Vector2d &candidate, double apparentWidth, const LineObjectOptions &object,
                                            const StartingPointOptions &options )
    {
      // direction: the orientation along which the band stands out most against both sides
      const double w0 = std::clamp( apparentWidth, object.minWidthPx, object.maxWidthPx );
      const double probe = options.probeLengthPx > 0.0 ? options.probeLengthPx : std::max( 24.0, 3.0 * w0 );
      double bestScore = -1e9;
      Eigen::Vector2d bestDirection = Eigen::Vector2d::UnitX();
      for ( int k = 0; k < options.directions; ++k )
      {
        const double angle = kPi * k / options.directions;
        const Eigen::Vector2d d( std::cos( angle ), std::sin( angle ) );
        const Eigen::Vector2d n = normalOf( d );
        const double side = 0.5 * w0 + 1.5; // just outside the band, where its sides are
        const auto [centreMean, centreSd] = meanAlong( grey, candidate, d, probe, object.polarity );
        const double left = meanAlong( grey, candidate + side * n, d, probe, object.polarity ).first;
        const double right = meanAlong( grey, candidate - side * n, d, probe, object.polarity ).first;
        if ( std::isnan( centreMean ) || std::isnan( left ) || std::isnan( right ) )
          continue;
        const double score = ( object.polarity != 0 ? centreMean - std::max( left, right ) : std::min( std::abs( centreMean - left ), std::abs( centreMean - right ) ) ) -
                             0.5 * centreSd;
        if ( score > bestScore )
        {
          bestScore = score;
          bestDirection = d;
        }
      }
      if ( bestScore < 0.4 * object.minContrast )
        return std::nullopt;
      // three profiles across: contrast, width, straightness
      const double search = 0.5 * w0 + 2.0;
      const std::optional<CrossSection> mid = bandAcross( grey, candidate, bestDirection, object, search );
      if ( !mid )
        return std::nullopt;
      const Eigen::Vector2d n = normalOf( bestDirection );
      const Eigen::Vector2d centre = candidate + mid->offsetPx * n;
      const double reach = 0.5 * probe;
      const std::optional<CrossSection> ahead = bandAcross( grey, centre + reach * bestDirection, bestDirection, object, 0.5 * mid->widthPx + 2.0 );
      const std::optional<CrossSection> behind = bandAcross( grey, centre - reach * bestDirection, bestDirection, object, 0.5 * mid->widthPx + 2.0 );
      if ( !ahead || !behind )
        return std::nullopt;

      // the middle centre lies at offset 0; the outer two at their offsets
      if ( std::abs( 0.5 * ( ahead->offsetPx + behind->offsetPx ) ) > options.straightnessPx )
        return std::nullopt;
      const double meanWidth = ( ahead->widthPx + mid->widthPx + behind->widthPx ) / 3.0;
      for ( const double w : { ahead->widthPx, mid->widthPx, behind->widthPx } )
        if ( std::abs( w - meanWidth ) > options.widthChange * meanWidth )
          return std::nullopt;
      const Eigen::Vector2d a = centre + reach * bestDirection + ahead->offsetPx * n;
      const Eigen::Vector2d b = centre - reach * bestDirection + behind->offsetPx * n;
      // uniformity along the line, on three parallels inside the band (a centre marking on one of them does not decide)
      const Eigen::Vector2d along = ( a - b ).normalized();
      double spread = 1e9;
      for ( const double offset : { -0.25 * meanWidthOf( ahead, mid, behind ), 0.0, 0.25 * meanWidthOf( ahead, mid, behind ) } )
        spread = std::min( spread, meanAlong( grey, centre + offset * normalOf( along ), along, 2.0 * reach, object.polarity ).second );
      if ( spread > object.maxVariation )
        return std::nullopt;
      LineState state;
      state.pixelInImage = centre;
      state.direction = along;
      state.widthPx = meanWidth;
      state.contrast = std::min( { ahead->contrast, mid->contrast, behind->contrast } );
      state.tone = mid->tone;
      return state;
    }
  } // namespace

  void StartingPointOptions::check() const
  {
    if ( sampleSpacingPx < 4 )
      throw std::invalid_argument( "the sample lines for starting points must be at least 4 px apart" );
    if ( probeLengthPx < 0.0 || directions < 4 || !( straightnessPx > 0.0 ) || !( widthChange > 0.0 ) )
      throw std::invalid_argument( "the starting-point tests need a non-negative probe length, at least 4 directions and positive tolerances" );
  }

  StartingPointSummary findStartingPoints( const cv::Mat &grey, const cv::Rect &area, const LineObjectOptions &object, const StartingPointOptions &options )
  {
    StartingPointSummary summary;
    const cv::Rect inside = area & cv::Rect( 0, 0, grey.cols, grey.rows );
    if ( inside.empty() )
      return summary;
    // bands crossed obliquely look wider on a sample line: allow up to 45 degrees
    const double apparentMax = 1.45 * object.maxWidthPx;
    const double margin = object.maxWidthPx + 8.0;
    std::vector<LineState> points;
    const auto scan = [&]( const Eigen::Vector2d &centre, const Eigen::Vector2d &along, int halfLength )
    {
      // a profile "across" a direction perpendicular to the sample line runs along the sample line
      const Eigen::Vector2d lineDirection = -normalOf( along ); // normalOf(lineDirection) == along
      const std::vector<double> profile = sampleCrossProfile( grey, centre, lineDirection, halfLength, object.polarity, 1.0, 3 );
      for ( const CrossSection &s : findCrossSections( profile, object.minWidthPx, apparentMax, object.minContrast, object.maxVariation, false, object.polarity ) )
      {
        ++summary.candidates;
        const Eigen::Vector2d p = centre + s.offsetPx * along;
        if ( p.x() < margin || p.y() < margin || p.x() > grey.cols - margin || p.y() > grey.rows - margin )
          continue;
        if ( std::optional<LineState> state = testCandidate( grey, p, s.widthPx, object, options ) )
        {
          bool duplicate = false;
          for ( const LineState &q : points )
            duplicate = duplicate || ( q.pixelInImage - state->pixelInImage ).norm() < std::max( q.widthPx, 6.0 );
          if ( !duplicate )
            points.push_back( *state );
        }
      }
    };
    const int s = options.sampleSpacingPx;
    for ( int row = inside.y + s / 2; row < inside.y + inside.height; row += s )
    {
      const int half = inside.width / 2;
      scan( Eigen::Vector2d( inside.x + half + 0.5, row + 0.5 ), Eigen::Vector2d::UnitX(), half );
    }
    for ( int col = inside.x + s / 2; col < inside.x + inside.width; col += s )
    {
      const int half = inside.height / 2;
      scan( Eigen::Vector2d( col + 0.5, inside.y + half + 0.5 ), Eigen::Vector2d::UnitY(), half );
    }
    // strongest and widest first: a road before the markings, kerbs and shoulders along it (contrast x sqrt(width))
    std::stable_sort( points.begin(), points.end(),
                      []( const LineState &a, const LineState &b ) { return a.contrast * std::sqrt( a.widthPx ) > b.contrast * std::sqrt( b.widthPx ); } );
    summary.points = std::move( points );
    return summary;
  }

} // namespace geostation
