/***************************************************************************
  linefollower.cpp - one road line through one image, gaps bridged
 ***************************************************************************/
#include "tracing/linefollower.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "imageproc/edgeprimitives.h"
#include "tracing/lineprofile.h"

namespace geostation
{
  namespace
  {
    FollowResult runMethod( const cv::Mat &grey, const FollowRequest &request, TraceMethod method, const LineFollowOptions &options )
    {
      switch ( method )
      {
        case TraceMethod::Directional:
          return followDirectional( grey, request, options.directional );
        case TraceMethod::LeastSquares:
          return followLeastSquares( grey, request, options.leastSquares );
        case TraceMethod::Polynomial:
          return followPolynomial( grey, request, options.polynomial );
        case TraceMethod::Auto:
          break;
      }
      throw std::invalid_argument( "followLine needs a method, not auto" );
    }

    //! The direction of the last `reachPx` of a polyline.
    Eigen::Vector2d endDirection( const std::vector<Eigen::Vector2d> &points, const Eigen::Vector2d &fallback, double reachPx )
    {
      if ( points.size() < 2 )
        return fallback;
      const Eigen::Vector2d end = points.back();
      for ( size_t i = points.size() - 1; i-- > 0; )
        if ( ( end - points[i] ).norm() >= reachPx || i == 0 )
        {
          const Eigen::Vector2d d = end - points[i];
          return d.norm() > 3.0 ? d.normalized() : fallback;
        }
      return fallback;
    }

    /**
     * The line's sides along the last `reachPx` of the followed points, every
     * 3 px: each side's median, so a few pixels slid onto an obstacle's outline
     * at the end do not count. Nothing for fewer than 3 places.
     */
    std::optional<LineSides> recentSides( const cv::Mat &grey, const std::vector<Eigen::Vector2d> &points, const LineProfile &profile, double reachPx )
    {
      std::vector<double> left, right, contrast;
      double along = 0.0, sampledAt = -3.0;
      for ( size_t i = points.size(); i-- > 0 && along <= reachPx; )
      {
        if ( i + 1 < points.size() )
          along += ( points[i + 1] - points[i] ).norm();
        if ( along - sampledAt < 3.0 )
          continue;
        // the direction of travel here: the chord over about 4 px each way
        size_t behind = i, ahead = i;
        while ( behind > 0 && ( points[i] - points[behind] ).norm() < 4.0 )
          --behind;
        while ( ahead + 1 < points.size() && ( points[ahead] - points[i] ).norm() < 4.0 )
          ++ahead;
        const Eigen::Vector2d chord = points[ahead] - points[behind];
        if ( chord.norm() < 2.0 )
          continue;
        if ( const std::optional<LineSides> sides = lineSides( grey, points[i], chord.normalized(), profile ) )
        {
          left.push_back( sides->left );
          right.push_back( sides->right );
          contrast.push_back( sides->contrast );
          sampledAt = along;
        }
      }
      if ( left.size() < 3 )
        return std::nullopt;
      const auto median = []( std::vector<double> &v ) {
        std::nth_element( v.begin(), v.begin() + v.size() / 2, v.end() );
        return v[v.size() / 2];
      };
      return LineSides { median( left ), median( right ), median( contrast ) };
    }
    //! Where a bridge starts: its first point, its direction (unit) and where the line was last followed.
    struct BridgeStart
    {
      Eigen::Vector2d from, direction, gapFrom;
    };

    //! What a bridge found: the hit the line resumes at, or nothing and why it stopped.
    struct BridgeScan
    {
      std::optional<LineHit> hit;
      TraceStop stop = TraceStop::EndOfLine;
    };

    /**
     * Looks for the line beyond a gap: straight ahead from the bridge's start,
     * a cross-section every 3 px; the first hit confirmed 2.5 px further on,
     * with on its sides what lay beside the line before the gap (`points`, the
     * line followed so far), resumes it. The image's border, the distance
     * limit and the largest gap (on the ground where known, counted from
     * where the line was last followed) end the search.
     */
    BridgeScan scanBridge( const cv::Mat &grey, const BridgeStart &bridge, const FollowRequest &current, TraceMethod method, const LineProfile &profile,
                           const std::vector<Eigen::Vector2d> &points, const LineFollowOptions &options )
    {
      const Eigen::Vector2d &d = bridge.direction;
      BridgeScan out;
      // what lies beside the line before the gap (over its last 100 px: a follower may have run along an
      // obstacle's outline for a while before it lost the line): a hit beyond it must have the like on its
      // sides (measured at the first hit: most bridges find none)
      std::optional<LineSides> sidesBefore;
      bool sidesMeasured = options.sideTolerance <= 0.0;
      LocateOptions locate = locateOptionsFor( profile, options.directional.follow, 2.0 );
      locate.minWidthRatio = 6.0; // a stripe narrows with distance across a long gap
      int partial = 0;
      // (bounded also by the image: a bridge never scans further than the image's diagonal)
      const double diagonal = std::hypot( grey.cols, grey.rows );
      for ( double s = 3.0; s <= diagonal; s += 3.0 )
      {
        const Eigen::Vector2d q = bridge.from + s * d;
        if ( !sampleGrey( grey, q - 4.0 * rightNormal( d ) ) || !sampleGrey( grey, q + 4.0 * rightNormal( d ) ) )
        {
          out.stop = TraceStop::LeftImage;
          break;
        }
        if ( current.withinLimit && !current.withinLimit( q ) )
        {
          out.stop = TraceStop::DistanceLimit;
          break;
        }
        const std::optional<double> ground = options.groundDistanceM ? options.groundDistanceM( bridge.gapFrom, q ) : std::nullopt;
        if ( ground ? *ground > options.maxGapM : ( q - bridge.gapFrom ).norm() > options.maxGapPx )
        {
          out.stop = partial > 0 ? TraceStop::GapTooLarge : TraceStop::EndOfLine;
          break;
        }
        // worn paint: the visible part of a stripe may lie to either side of the line, up to half its width
        // (the polynomial strips span short worn patches; the skeleton and least squares stop at them)
        const bool wornSide = method != TraceMethod::Polynomial && profile.kind != LineKind::Edge;
        locate.searchHalfPx = 3.0 + 0.1 * s + ( wornSide ? 0.5 * profile.widthPx : 0.0 );
        const std::optional<LineHit> hit = locateLine( grey, q, d, profile, locate );
        if ( !hit )
          continue;
        ++partial;
        // confirmed a little further on (a far dash is only a few pixels long)
        LocateOptions confirm = locate;
        confirm.searchHalfPx = 2.0;
        const std::optional<LineHit> further = locateLine( grey, hit->pixelInImage + 2.5 * d, d, profile, confirm );
        if ( !further )
          continue;
        if ( !sidesMeasured )
        {
          sidesBefore = recentSides( grey, points, profile, 100.0 );
          sidesMeasured = true;
        }
        if ( sidesBefore )
        {
          const std::optional<LineSides> seen = lineSides( grey, hit->pixelInImage, d, profile );
          if ( !seen || !sidesAgree( *sidesBefore, *seen, std::max( 4.0, options.sideTolerance * sidesBefore->contrast ) ) )
            continue;
        }
        out.hit = hit;
        out.stop = TraceStop::EndOfLine;
        break;
      }
      return out;
    }

    /**
     * The vertices: Douglas-Peucker on each followed run (`runStarts`: the
     * index of each run's first point), each kept point with its sigma; the
     * runs are joined by bridged segments (`bridged` set on a run's first vertex).
     */
    void vectoriseRuns( const std::vector<Eigen::Vector2d> &points, const std::vector<double> &sigmas, std::vector<size_t> runStarts, double tolerancePx, FollowResult &line )
    {
      runStarts.push_back( points.size() );
      for ( size_t r = 0; r + 1 < runStarts.size(); ++r )
      {
        const std::vector<Eigen::Vector2d> run( points.begin() + runStarts[r], points.begin() + runStarts[r + 1] );
        if ( run.empty() )
          continue;
        size_t j = runStarts[r];
        bool first = true;
        for ( const Eigen::Vector2d &k : douglasPeucker( run, tolerancePx ) )
        {
          while ( j < runStarts[r + 1] && ( points[j] - k ).norm() > 1e-9 )
            ++j;
          line.points.push_back( k );
          line.sigmaPx.push_back( j < sigmas.size() ? sigmas[j] : 0.5 );
          line.bridged.push_back( first && !line.bridged.empty() );
          first = false;
        }
      }
    }
  }

  LineFollowResult followLine( const cv::Mat &grey, const FollowRequest &request, TraceMethod method, const LineFollowOptions &options )
  {
    LineFollowResult out;
    FollowRequest current = request;
    std::vector<Eigen::Vector2d> points;
    std::vector<double> sigmas;
    std::vector<size_t> runStarts { 0 }; // the followed runs between bridged gaps
    FollowResult last;
    struct BridgeState
    {
      Eigen::Vector2d from, direction;
      size_t points = 0;
      LineProfile profile;
    };
    std::optional<BridgeState> lastBridge;
    // where the line was last followed: a hit beyond a gap that least squares then follows for less than
    // LineFollowOptions::minLegPx is no line found (on cobbles or gravel, bridge after bridge finds a
    // seam and follows nothing); the gap goes on from here, and such hits at the end are dropped. (The
    // skeleton and the strips follow nothing of a far dash they reach either: for them every hit counts.)
    const double minLegPx = method == TraceMethod::LeastSquares ? options.minLegPx : 0.0;
    Eigen::Vector2d gapFrom = request.start;
    size_t followedPoints = 0;
    int followedGaps = 0;
    double followedGapPx = 0.0;
    for ( int leg = 0; leg < 64; ++leg )
    {
      last = runMethod( grey, current, method, options );
      for ( size_t i = 0; i < last.points.size(); ++i )
        if ( points.empty() || ( last.points[i] - points.back() ).norm() > 0.25 )
        {
          points.push_back( last.points[i] );
          sigmas.push_back( last.sigmaPx[i] );
        }
      out.line.pixelsFollowed += last.pixelsFollowed;
      const double legLength = last.points.empty() ? 0.0 : ( last.points.back() - last.points.front() ).norm();
      if ( leg == 0 || legLength >= minLegPx )
      {
        gapFrom = points.empty() ? current.start : points.back();
        followedPoints = points.size();
        followedGaps = out.bridgedGaps;
        followedGapPx = out.bridgedPx;
      }
      if ( last.stop != TraceStop::EndOfLine && last.stop != TraceStop::NoEdge )
        break;
      // bridge: straight ahead from the end (or from the start, when that lies in a gap), cross-sections every 3 px
      const Eigen::Vector2d from = points.empty() ? current.start : points.back();
      // the direction of the last 25 px; a short leg (a dash, a worn patch) keeps the direction it was given
      Eigen::Vector2d d = endDirection( points, current.direction, 25.0 );
      if ( legLength < 20.0 )
      {
        const Eigen::Vector2d blended = ( 20.0 - legLength ) * current.direction.normalized() + legLength * d;
        // (a short leg that turned back on the direction given: the direction given)
        d = blended.norm() > 1.0 ? blended.normalized() : current.direction.normalized();
      }
      // the same bridge as the last one, which found a hit the follower could not follow: it would find the
      // same hit and fail the same way again (while anything of it changes, it is tried again)
      const bool sameBridge = lastBridge && lastBridge->from == from && lastBridge->direction == d && lastBridge->points == points.size() &&
                              lastBridge->profile.widthPx == last.profile.widthPx && lastBridge->profile.contrast == last.profile.contrast &&
                              lastBridge->profile.polarity == last.profile.polarity && lastBridge->profile.kind == last.profile.kind;
      if ( sameBridge )
      {
        last.stop = TraceStop::EndOfLine;
        break;
      }
      lastBridge = BridgeState { from, d, points.size(), last.profile };
      const BridgeScan scan = scanBridge( grey, { from, d, gapFrom }, current, method, last.profile, points, options );
      last.stop = scan.stop;
      if ( !scan.hit )
        break;
      current.start = scan.hit->pixelInImage;
      current.direction = d;
      if ( !points.empty() )
        runStarts.push_back( points.size() );
      current.profile = last.profile;
      ++out.bridgedGaps;
      out.bridgedPx += ( scan.hit->pixelInImage - from ).norm();
    }
    // hits beyond the last place the line was followed, none of them followed, where the line was then lost:
    // not the line (where the image or the distance limit ended the bridge after them, they are kept)
    const bool lost = last.stop == TraceStop::EndOfLine || last.stop == TraceStop::GapTooLarge || last.stop == TraceStop::NoEdge;
    if ( lost && points.size() > followedPoints && followedPoints > 0 )
    {
      points.resize( followedPoints );
      sigmas.resize( followedPoints );
      while ( !runStarts.empty() && runStarts.back() >= followedPoints )
        runStarts.pop_back();
      if ( runStarts.empty() )
        runStarts.push_back( 0 );
      out.bridgedGaps = followedGaps;
      out.bridgedPx = followedGapPx;
    }
    out.line.stop = last.stop;
    out.line.profile = last.profile;
    out.line.direction = endDirection( points, last.direction, 25.0 );
    vectoriseRuns( points, sigmas, runStarts, options.vertexTolerancePx, out.line );
    return out;
  }

  LineFollowResult followLineBothWays( const cv::Mat &grey, const FollowRequest &request, TraceMethod method, const LineFollowOptions &options )
  {
    LineFollowResult ahead = followLine( grey, request, method, options );
    FollowRequest backwardRequest = request;
    backwardRequest.direction = -request.direction;
    if ( request.profile.kind == LineKind::Edge )
      backwardRequest.profile.polarity = -request.profile.polarity;
    const LineFollowResult behind = followLine( grey, backwardRequest, method, options );
    joinBackward( behind.line, ahead.line );
    ahead.line.pixelsFollowed += behind.line.pixelsFollowed;
    ahead.bridgedGaps += behind.bridgedGaps;
    ahead.bridgedPx += behind.bridgedPx;
    return ahead;
  }

} // namespace geostation
