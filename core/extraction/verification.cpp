/***************************************************************************
  verification.cpp - a line of one image confirmed in its partner
 ***************************************************************************/
#include "extraction/verification.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>

#include "extraction/areaofinterest.h"
#include "extraction/regionalextraction.h"

namespace geostation
{

  void VerificationOptions::check() const
  {
    if ( !( misregistrationPx > 0.0 ) || !( trackingHalfWidthPx > 0.0 ) || !( areaLengthPx >= 8.0 ) )
      throw std::invalid_argument( "verification needs a positive misregistration and tracking width and areas of at least 8 px" );
    if ( !( minChainConfidence > 0.0 ) || minChainLinks < 2 || !( maxAngleDeg > 0.0 && maxAngleDeg < 80.0 ) )
      throw std::invalid_argument( "verification needs a positive chain confidence, at least 2 links and an angle limit below 80 degrees" );
    if ( deadEndReachPx < 0.0 || !( densifyPx > 0.0 ) )
      throw std::invalid_argument( "verification's dead-end reach must not be negative and its sampling must be positive" );
  }

  std::vector<Eigen::Vector2d> densifyPolyline( const std::vector<Eigen::Vector2d> &polyline, double stepPx )
  {
    std::vector<Eigen::Vector2d> out;
    if ( polyline.empty() )
      return out;
    out.push_back( polyline.front() );
    for ( size_t i = 1; i < polyline.size(); ++i )
    {
      const Eigen::Vector2d a = polyline[i - 1], b = polyline[i];
      const int n = std::max( 1, static_cast<int>( std::ceil( ( b - a ).norm() / stepPx ) ) );
      for ( int k = 1; k <= n; ++k )
        out.push_back( a + ( b - a ) * ( static_cast<double>( k ) / n ) );
    }
    return out;
  }

  std::optional<CrossSection> bandAt( const GreyTiles &grey, const Eigen::Vector2d &pixelInImage, const Eigen::Vector2d &direction, const LineObjectOptions &object )
  {
    const int half = static_cast<int>( std::ceil( object.maxWidthPx ) ) + 6;
    // the profile's pixels: half across, 2 along, 2 for interpolation
    const GreyWindow w = grey.around( pixelInImage, half + 6 );
    const std::vector<double> profile = sampleCrossProfile( w.pixels, w.toWindow( pixelInImage ), direction, half, object.polarity, 2.0, 3 );
    std::optional<CrossSection> best;
    for ( const CrossSection &s : findCrossSections( profile, object.minWidthPx, object.maxWidthPx, object.minContrast, object.maxVariation, false, object.polarity ) )
      if ( std::abs( s.offsetPx ) <= 3.0 && ( !best || std::abs( s.offsetPx ) < std::abs( best->offsetPx ) ) )
        best = s;
    return best;
  }

  namespace
  {
    /**
     * The band's width at the wider end of the stretch where it was found
     * over that at the narrower end, by a straight line fitted to the widths
     * against the distance along; 1 where the widths do not follow a straight
     * line (within 15 % of their mean, RMS) or the stretch is shorter than 4
     * widths.
     */
    double steadyWidening( const std::vector<std::pair<double, double>> &alongWidth )
    {
      const double n = static_cast<double>( alongWidth.size() );
      if ( alongWidth.size() < 10 )
        return 1.0;
      double sa = 0.0, sw = 0.0, saa = 0.0, saw = 0.0;
      for ( const auto &[a, w] : alongWidth )
      {
        sa += a;
        sw += w;
        saa += a * a;
        saw += a * w;
      }
      const double denominator = n * saa - sa * sa, mean = sw / n;
      const double first = alongWidth.front().first, last = alongWidth.back().first;
      if ( !( denominator > 0.0 ) || last - first < 4.0 * mean )
        return 1.0;
      const double slope = ( n * saw - sa * sw ) / denominator, intercept = ( sw - slope * sa ) / n;
      double squares = 0.0;
      for ( const auto &[a, w] : alongWidth )
        squares += ( w - intercept - slope * a ) * ( w - intercept - slope * a );
      if ( std::sqrt( squares / n ) > 0.15 * mean )
        return 1.0;
      const double atFirst = intercept + slope * first, atLast = intercept + slope * last;
      return std::max( atFirst, atLast ) / std::max( 1.0, std::min( atFirst, atLast ) );
    }
  } // namespace

  BandSupport bandSupport( const GreyTiles &grey, const std::vector<Eigen::Vector2d> &line, const LineObjectOptions &object, bool trimStart, bool trimEnd )
  {
    const std::vector<Eigen::Vector2d> samples = densifyPolyline( line, 2.0 );
    if ( samples.size() < 3 )
      return {};
    std::vector<double> along( samples.size(), 0.0 );
    for ( size_t i = 1; i < samples.size(); ++i )
      along[i] = along[i - 1] + ( samples[i] - samples[i - 1] ).norm();
    std::vector<std::optional<CrossSection>> sections( samples.size() - 1 );
    std::vector<bool> looked( samples.size() - 1, false );
    std::vector<double> widths;
    for ( size_t i = 0; i + 1 < samples.size(); ++i )
      if ( const Eigen::Vector2d step = samples[i + 1] - samples[i]; step.norm() > 1e-9 )
      {
        looked[i] = true;
        sections[i] = bandAt( grey, samples[i], step.normalized(), object );
        if ( sections[i] )
          widths.push_back( sections[i]->widthPx );
      }
    // a junction's mouth: within twice the band's width of the junction the profiles cross the other road
    double trim = 0.0;
    if ( ( trimStart || trimEnd ) && !widths.empty() )
    {
      std::nth_element( widths.begin(), widths.begin() + widths.size() / 2, widths.end() );
      trim = 2.0 * widths[widths.size() / 2];
    }
    int found = 0, counted = 0;
    std::vector<std::pair<double, double>> alongWidth;
    for ( size_t i = 0; i + 1 < samples.size(); ++i )
    {
      if ( !looked[i] || ( trimStart && along[i] < trim ) || ( trimEnd && along[i] > along.back() - trim ) )
        continue;
      ++counted;
      if ( sections[i] )
      {
        ++found;
        alongWidth.emplace_back( along[i], sections[i]->widthPx );
      }
    }
    BandSupport support;
    support.share = counted > 0 ? static_cast<double>( found ) / counted : 1.0;
    support.widening = steadyWidening( alongWidth );
    return support;
  }

  std::pair<double, double> measureBand( const GreyTiles &grey, const std::vector<Eigen::Vector2d> &line, const LineObjectOptions &object )
  {
    std::vector<double> widths, contrasts;
    for ( int k = 1; k <= 7 && line.size() > 2; ++k )
    {
      const size_t i = std::min( line.size() - 2, line.size() * k / 8 );
      if ( const std::optional<CrossSection> best = bandAt( grey, line[i], ( line[i + 1] - line[i] ).normalized(), object ) )
      {
        widths.push_back( best->widthPx );
        contrasts.push_back( best->contrast );
      }
    }
    if ( widths.empty() )
      return { 0.5 * ( object.minWidthPx + object.maxWidthPx ), 1.5 * object.minContrast };
    std::nth_element( widths.begin(), widths.begin() + widths.size() / 2, widths.end() );
    std::nth_element( contrasts.begin(), contrasts.begin() + contrasts.size() / 2, contrasts.end() );
    return { widths[widths.size() / 2], contrasts[contrasts.size() / 2] };
  }

  namespace
  {
    struct Interval
    {
      double from, to;
      std::vector<Eigen::Vector2d> target;
    };

    Eigen::Vector2d pointAt( const std::vector<Eigen::Vector2d> &line, const std::vector<double> &u, double s )
    {
      const size_t i = std::upper_bound( u.begin(), u.end(), s ) - u.begin();
      if ( i == 0 )
        return line.front();
      if ( i >= line.size() )
        return line.back();
      const double span = u[i] - u[i - 1];
      return span > 0 ? Eigen::Vector2d( line[i - 1] + ( line[i] - line[i - 1] ) * ( ( s - u[i - 1] ) / span ) ) : line[i];
    }

    //! Verifies one run of a polygon whose mapping is defined throughout.
    void verifyRun( const GreyTiles &targetGrey, const std::vector<Eigen::Vector2d> &source, const std::vector<Eigen::Vector2d> &mapped,
                    double widthPx, double contrast, const LineObjectOptions &object, const VerificationOptions &options, VerificationSummary &summary )
    {
      std::vector<double> u( mapped.size(), 0.0 );
      for ( size_t i = 1; i < mapped.size(); ++i )
        u[i] = u[i - 1] + ( mapped[i] - mapped[i - 1] ).norm();
      const double total = u.back();
      const double spacing = std::clamp( widthPx / 3.0, 2.0, 4.0 );
      if ( total < 3 * spacing )
        return;
      AreaAnalysisOptions analysis;
      analysis.polarity = object.polarity;
      analysis.widthPx = widthPx;
      analysis.contrast = contrast;
      analysis.maxAngleDeg = options.maxAngleDeg;
      analysis.maxGapLines = static_cast<int>( std::ceil( 2.0 * widthPx / spacing ) );

      std::vector<Interval> found;
      double offset = 0.0;
      bool tracking = false;
      for ( double from = 0.0; from < total - 2 * spacing; )
      {
        const double to = std::min( total, from + options.areaLengthPx );
        const Eigen::Vector2d a = pointAt( mapped, u, from ), b = pointAt( mapped, u, to );
        if ( ( b - a ).norm() < 1.0 )
          break;
        // around the mapped line within the misregistration; once found, around the line, but never further from
        // the mapped line than the misregistration (tracking must not walk off onto a line beside it)
        double centre = 0.0, halfWidth = options.misregistrationPx;
        if ( tracking )
        {
          const double low = std::max( offset - options.trackingHalfWidthPx, -options.misregistrationPx );
          const double high = std::min( offset + options.trackingHalfWidthPx, options.misregistrationPx );
          centre = 0.5 * ( low + high );
          halfWidth = 0.5 * ( high - low );
          if ( halfWidth < 1.0 )
          {
            centre = 0.0;
            halfWidth = options.misregistrationPx;
          }
        }
        AreaOfInterest area;
        area.axis = ( b - a ).normalized();
        area.spacingPx = spacing;
        area.origin = a - spacing * area.axis + centre * normalOf( area.axis );
        area.lengthPx = ( b - a ).norm() + spacing;
        area.halfWidthPx = halfWidth;
        // the area's pixels: its profiles (half-width + width + 3 across, half a spacing along) and the refinement of
        // its chain's points (1.6 widths + 6 across), read as one window
        const GreyWindow w = targetGrey.covering( area.origin, area.origin + area.lengthPx * area.axis,
                                                  static_cast<int>( std::ceil( area.halfWidthPx + 2.0 * widthPx + area.spacingPx ) ) + 12 );
        AreaOfInterest local = area;
        local.origin = w.toWindow( area.origin );
        const std::vector<ChainLink> chain = bestChain( analyseArea( w.pixels, local, analysis ), local, analysis, std::nullopt );
        double mean = 0.0;
        for ( const ChainLink &link : chain )
          mean += link.confidence / chain.size();
        if ( static_cast<int>( chain.size() ) >= options.minChainLinks && mean >= options.minChainConfidence )
        {
          Interval interval;
          interval.from = from + chain.front().line * spacing;
          interval.to = from + chain.back().line * spacing;
          double lastOffsets = 0.0;
          int counted = 0;
          for ( size_t k = 0; k < chain.size(); ++k )
          {
            Eigen::Vector2d p = local.pointOn( chain[k].line, chain[k].offsetPx );
            if ( const std::optional<CrossSection> refined = refineAcross( w.pixels, p, area.axis, widthPx, object, 2.0 ) )
              p += refined->offsetPx * normalOf( area.axis );
            interval.target.push_back( w.toImage( p ) );
            if ( k + 3 >= chain.size() )
            {
              lastOffsets += chain[k].offsetPx;
              ++counted;
            }
          }
          offset = centre + lastOffsets / counted;
          tracking = true;
          found.push_back( std::move( interval ) );
        }
        else
          tracking = false;
        from = to;
      }

      // merge areas whose lines join up
      std::vector<Interval> parts;
      for ( Interval &interval : found )
      {
        if ( !parts.empty() && interval.from - parts.back().to <= 2.0 * widthPx + 2 * spacing )
        {
          parts.back().to = interval.to;
          parts.back().target.insert( parts.back().target.end(), interval.target.begin(), interval.target.end() );
        }
        else
          parts.push_back( std::move( interval ) );
      }
      double covered = 0.0;
      const auto deadEnd = [&]( const std::vector<Eigen::Vector2d> &line, bool atStart, bool reachesEnd )
      {
        DeadEnd d;
        const Eigen::Vector2d end = atStart ? line.front() : line.back();
        const Eigen::Vector2d inner = atStart ? line[std::min<size_t>( 3, line.size() - 1 )] : line[line.size() - 1 - std::min<size_t>( 3, line.size() - 1 )];
        d.state.pixelInImage = end;
        d.state.direction = ( end - inner ).norm() > 0 ? Eigen::Vector2d( ( end - inner ).normalized() ) : Eigen::Vector2d::UnitX();
        d.state.widthPx = widthPx;
        d.state.contrast = contrast;
        d.kind = reachesEnd ? DeadEndKind::Verification : DeadEndKind::Unverified;
        ( reachesEnd ? summary.continueFrom : summary.finalDeadEnds ).push_back( d );
      };
      for ( const Interval &part : parts )
      {
        if ( part.target.size() < 2 )
          continue;
        VerifiedPart accepted;
        accepted.inTarget = part.target;
        for ( size_t i = 0; i < source.size(); ++i )
          if ( u[i] >= part.from - 1e-9 && u[i] <= part.to + 1e-9 )
            accepted.inSource.push_back( source[i] );
        if ( accepted.inSource.size() < 2 )
          continue;
        covered += part.to - part.from;
        deadEnd( accepted.inTarget, true, part.from <= options.deadEndReachPx );
        deadEnd( accepted.inTarget, false, part.to >= total - options.deadEndReachPx );
        summary.accepted.push_back( std::move( accepted ) );
      }
      summary.sourceLengthPx += total;
      summary.acceptedSourceLengthPx += covered;
      if ( covered >= 0.9 * total )
        ++summary.wholly;
      else if ( covered > 0 )
        ++summary.partly;
      else
        ++summary.rejected;
    }
  } // namespace

  VerificationSummary verifyPolygons( const cv::Mat &sourceGrey, const cv::Mat &targetGrey, const std::vector<CompiledPolygon> &polygons,
                                      const PixelMap &sourceToTarget, const LineObjectOptions &object, const VerificationOptions &options )
  {
    if ( sourceGrey.type() != CV_8UC1 || targetGrey.type() != CV_8UC1 )
      throw std::invalid_argument( "verification needs 8-bit single-band images" );
    return verifyPolygons( GreyTiles( sourceGrey ), GreyTiles( targetGrey ), polygons, sourceToTarget, object, options );
  }

  VerificationSummary verifyPolygons( const GreyTiles &sourceGrey, const GreyTiles &targetGrey, const std::vector<CompiledPolygon> &polygons,
                                      const PixelMap &sourceToTarget, const LineObjectOptions &object, const VerificationOptions &options )
  {
    options.check();
    object.check();
    const auto start = std::chrono::steady_clock::now();
    VerificationSummary summary;
    for ( const CompiledPolygon &polygon : polygons )
    {
      const std::vector<Eigen::Vector2d> source = densifyPolyline( polygon.pixels, options.densifyPx );
      if ( source.size() < 3 )
        continue;
      // (not a structured binding: lambdas capture those only from C++20 on)
      const std::pair<double, double> band = measureBand( sourceGrey, source, object );
      const double width = band.first, contrast = band.second;
      std::vector<Eigen::Vector2d> runSource, runTarget;
      const auto flush = [&]
      {
        if ( runSource.size() >= 3 )
          verifyRun( targetGrey, runSource, runTarget, width, contrast, object, options, summary );
        runSource.clear();
        runTarget.clear();
      };
      for ( const Eigen::Vector2d &p : source )
      {
        const std::optional<Eigen::Vector2d> q = sourceToTarget( p );
        if ( q && q->x() >= 0 && q->y() >= 0 && q->x() <= targetGrey.width() && q->y() <= targetGrey.height() )
        {
          runSource.push_back( p );
          runTarget.push_back( *q );
        }
        else
          flush();
      }
      flush();
    }
    summary.seconds = std::chrono::duration<double>( std::chrono::steady_clock::now() - start ).count();
    return summary;
  }

} // namespace geostation
