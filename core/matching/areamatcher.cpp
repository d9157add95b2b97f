/***************************************************************************
  areamatcher.cpp - epipolar band and 2-D correlation search, then LSM
 ***************************************************************************/
#include "matching/areamatcher.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <map>
#include <set>
#include <stdexcept>

#include <Eigen/LU>
#include <Eigen/SVD>
#include <opencv2/core.hpp>

namespace geostation
{
  namespace
  {
    struct Candidate
    {
      int col, row;
      int along; //!< index along the curve, for the jump rule and peak separation
      bool border = false; //!< on the border of a 2-D search area: a neighbour lies outside it
    };

    /**
     * The part of segment a-b inside the rectangle [lo, hi] (Liang-Barsky);
     * false when none. Curve vertices far outside the frame (a depth near
     * the search camera's plane projects to huge pixel values) are cut off here.
     */
    bool clipSegment( Eigen::Vector2d &a, Eigen::Vector2d &b, const Eigen::Vector2d &lo, const Eigen::Vector2d &hi )
    {
      if ( !a.allFinite() || !b.allFinite() )
        return false;
      const Eigen::Vector2d d = b - a;
      double t0 = 0.0, t1 = 1.0;
      for ( int k = 0; k < 2; ++k )
      {
        const double p[2] = { -d[k], d[k] }, q[2] = { a[k] - lo[k], hi[k] - a[k] };
        for ( int j = 0; j < 2; ++j )
        {
          if ( p[j] == 0.0 )
          {
            if ( q[j] < 0 )
              return false;
            continue;
          }
          const double t = q[j] / p[j];
          if ( p[j] < 0 )
            t0 = std::max( t0, t );
          else
            t1 = std::min( t1, t );
        }
      }
      if ( t0 > t1 )
        return false;
      b = a + t1 * d;
      a = a + t0 * d;
      return true;
    }

    //! Integer pixels (col, row index) of the curve at 1 px steps and of its parallels, within the search image.
    std::vector<Candidate> bandCandidates( const std::vector<Eigen::Vector2d> &curve, int halfWidth, int width, int height )
    {
      std::vector<Candidate> out;
      std::set<std::pair<int, int>> seen;
      const Eigen::Vector2d lo( -halfWidth - 1.0, -halfWidth - 1.0 ), hi( width + halfWidth + 1.0, height + halfWidth + 1.0 );
      int along = 0;
      for ( size_t i = 0; i + 1 < curve.size(); ++i )
      {
        Eigen::Vector2d a = curve[i], b = curve[i + 1];
        if ( !clipSegment( a, b, lo, hi ) )
          continue;
        const double length = ( b - a ).norm();
        if ( length <= 0.0 )
          continue;
        const Eigen::Vector2d direction = ( b - a ) / length, normal( -direction.y(), direction.x() );
        const int steps = std::max( 1, static_cast<int>( std::ceil( length ) ) );
        for ( int s = 0; s < steps; ++s )
        {
          const Eigen::Vector2d p = a + direction * ( length * s / steps );
          bool added = false;
          for ( int o = -halfWidth; o <= halfWidth; ++o )
          {
            const Eigen::Vector2d q = p + normal * o;
            const int col = static_cast<int>( std::floor( q.x() ) ), row = static_cast<int>( std::floor( q.y() ) );
            if ( seen.insert( { col, row } ).second )
            {
              out.push_back( { col, row, along } );
              added = true;
            }
          }
          along += added ? 1 : 0;
        }
      }
      return out;
    }

    constexpr int kMaxGrownWindow = 41; //!< the largest least-squares window a predicted shape may ask for
    constexpr double kCorrelationSigmaPx = 0.5; //!< the precision of a correlation peak without LSM (thesis: about a pixel at worst)

    //! Grey-value standard deviation of the reference window least squares matches (0 if it leaves the image).
    double windowContrast( const MatchImage &image, const Eigen::Vector2d &pixel, int width, int height )
    {
      const int c0 = static_cast<int>( std::floor( pixel.x() ) ) - width / 2, r0 = static_cast<int>( std::floor( pixel.y() ) ) - height / 2;
      const cv::Rect window( c0, r0, width, height );
      if ( !image.holds( window ) )
        return 0.0;
      cv::Scalar mean, sd;
      cv::meanStdDev( image.valueIn( window ), mean, sd );
      return sd[0];
    }

    double smallestScale( const Eigen::Matrix2d &shape )
    {
      return Eigen::JacobiSVD<Eigen::Matrix2d>( shape ).singularValues().minCoeff();
    }

    /**
     * Least squares started from a strong shape. Where the search image
     * shows the patch smaller, the reference window grows so that its
     * footprint there keeps the nominal size (a 9 x 9 window of a near image
     * covers a few pixels of a far one), and is smoothed to the search
     * image's resolution: a search pixel spans 1 / shrink reference pixels,
     * a box whose variance w^2 / 12 exceeds the reference pixel's own.
     */
    LsmOptions adaptedToShape( LsmOptions lsm, const Eigen::Matrix2d &searchFromReference )
    {
      lsm.initialAffine = searchFromReference;
      const double shrink = smallestScale( searchFromReference );
      if ( shrink >= 1.0 )
        return lsm;
      const auto grown = [&]( int size ) { return std::min( kMaxGrownWindow, static_cast<int>( std::ceil( size / std::max( shrink, 1e-3 ) ) ) | 1 ); };
      lsm.windowWidth = std::max( lsm.windowWidth, grown( lsm.windowWidth ) );
      lsm.windowHeight = std::max( lsm.windowHeight, grown( lsm.windowHeight ) );
      lsm.referenceBlurPx = std::max( lsm.referenceBlurPx, std::sqrt( ( 1.0 / ( shrink * shrink ) - 1.0 ) / 12.0 ) );
      return lsm;
    }

    //! Why a converged least-squares solution is still not a match ("" if it is one).
    std::string implausible( const LsmResult &lsm, double contrast, const Eigen::Matrix2d &expectedShape, const AreaMatchOptions &options )
    {
      if ( contrast > 0 && lsm.sigma0 > options.maxSigma0Ratio * contrast )
        return "least squares fits poorly (sigma0 " + std::to_string( lsm.sigma0 ).substr( 0, 5 ) + " grey values for a window contrast of " +
               std::to_string( contrast ).substr( 0, 5 ) + ")";
      const Eigen::JacobiSVD<Eigen::Matrix2d> svd( expectedShape.inverse() * lsm.affine );
      const Eigen::Vector2d scales = svd.singularValues();
      if ( scales.maxCoeff() > options.maxAffineScale || scales.minCoeff() < 1.0 / options.maxAffineScale )
        return "least squares found an implausible shape (scales " + std::to_string( scales.minCoeff() ).substr( 0, 4 ) + " and " +
               std::to_string( scales.maxCoeff() ).substr( 0, 4 ) + ")";
      return std::string();
    }

    //! A correlation template and the shape it stands for.
    struct WindowShape
    {
      const CorrelationTemplate *target = nullptr;
      Eigen::Matrix2d searchFromReference = Eigen::Matrix2d::Identity(); //!< least squares' starting shape
      Eigen::Vector2d offset = Eigen::Vector2d::Zero(); //!< the reference point's offset from the template's centre, carried to the peak
    };

    /**
     * Parabola refinement around an integer peak, then LSM from several
     * starts and its checks; fills the result. Without a peak inside the
     * search area (`peakInArea` false: the correlation is highest on its
     * border) the peak is as weak as one below the threshold: least squares
     * starts from the approximate position first, and its solution must lie
     * inside the area.
     */
    void refine( const MatchImage &reference, const Eigen::Vector2d &pixelInReference, const MatchImage &search, const WindowShape &shape,
                 int col, int row, bool peakInArea, const std::optional<Eigen::Vector2d> &approximate, double radiusPx, const AreaMatchOptions &options,
                 AreaMatch &result )
    {
      const auto scoreAt = [&]( int c, int r ) { return shape.target->score( search, c, r ).value_or( result.score ); };
      const double dx = parabolaPeakOffset( scoreAt( col - 1, row ), result.score, scoreAt( col + 1, row ) );
      const double dy = parabolaPeakOffset( scoreAt( col, row - 1 ), result.score, scoreAt( col, row + 1 ) );
      result.correlationPixel = Eigen::Vector2d( col + 0.5 + dx, row + 0.5 + dy ) + shape.offset;
      result.pixelInImage = result.correlationPixel;
      const bool weakPeak = !peakInArea || result.score < options.minScore;
      const std::string weakReason = !peakInArea ? "the correlation is highest on the border of the search area (" + std::to_string( result.score ).substr( 0, 5 ) +
                                                   "): there is no peak inside it"
                                                 : "best correlation " + std::to_string( result.score ).substr( 0, 5 ) + " is below the threshold " +
                                                   std::to_string( options.minScore ).substr( 0, 4 );
      // a weak peak still gets least squares from the approximate position (strong distortion lowers the
      // correlation of square windows; least squares' affine shape absorbs it), and its checks decide
      if ( weakPeak && ( !options.lsm || !approximate || !options.lsmBelowThreshold ) )
      {
        result.status = MatchStatus::NoPeak;
        result.message = weakReason;
        return;
      }
      const bool ambiguous = result.secondScore > result.score - options.ambiguityMargin;
      const auto correlationOnly = [&]( const std::string &why )
      {
        result.sigmaPx = kCorrelationSigmaPx;
        result.message = why;
        if ( ambiguous )
        {
          result.status = MatchStatus::Ambiguous;
          result.message = ( why.empty() ? std::string() : why + "; " ) + "a second peak scores " + std::to_string( result.secondScore ).substr( 0, 5 ) +
                          " against " + std::to_string( result.score ).substr( 0, 5 );
          return;
        }
        result.status = MatchStatus::Correlation;
      };
      if ( !options.lsm )
      {
        correlationOnly( std::string() );
        return;
      }

      // least squares from several starts: the correlation peak, the approximate position, the next peaks
      std::vector<Eigen::Vector2d> starts;
      if ( weakPeak )
        starts.push_back( *approximate );
      starts.push_back( result.correlationPixel );
      if ( approximate && !weakPeak )
        starts.push_back( *approximate );
      // (the best of them is the correlation peak, unless it lies on the border of a 2-D search area)
      for ( size_t k = 0; k < result.peaks.size() && static_cast<int>( starts.size() ) < std::max( 1, options.lsmStarts ); ++k )
        if ( ( result.peaks[k].first - result.correlationPixel ).norm() > 1.5 )
          starts.push_back( result.peaks[k].first );
      starts.resize( std::min<size_t>( starts.size(), std::max( 1, options.lsmStarts ) ) );
      // least squares from the winning window's shape, then (a point off the predicted surface, or a patch
      // that is part surface and part object) from the other one
      std::vector<std::optional<Eigen::Matrix2d>> shapes { result.shapedWindow ? options.predictedShape : std::nullopt };
      if ( options.predictedShape )
        shapes.push_back( result.shapedWindow ? std::nullopt : options.predictedShape );
      std::optional<LsmResult> best;
      bool degenerate = true, usedPredicted = false;
      std::string why;
      for ( const std::optional<Eigen::Matrix2d> &predicted : shapes )
      {
        if ( best )
          break;
        const LsmOptions lsmOptions = predicted ? adaptedToShape( options.lsmOptions, *predicted ) : options.lsmOptions;
        // the grey-value spread of the window least squares actually matches
        const double contrast = windowContrast( reference, pixelInReference, lsmOptions.windowWidth, lsmOptions.windowHeight );
        // a solution, or why it is no match: not converged, an implausible fit or shape, or another point beyond the search radius
        // (only the regular starts decide whether the window is a line or an edge least squares cannot fix)
        const auto attempt = [&]( const Eigen::Vector2d &start, const LsmOptions &lsm, bool regularStart ) -> std::optional<LsmResult>
        {
          const LsmResult r = leastSquaresMatch( reference, pixelInReference, search, start, lsm );
          std::string rejected;
          if ( !r.converged() )
            rejected = r.message;
          else if ( const std::string bad = implausible( r, contrast, lsmOptions.initialAffine, options ); !bad.empty() )
            rejected = bad;
          else if ( approximate && ( r.pixelInImage - *approximate ).norm() > radiusPx )
            rejected = "least squares left the search area: it moved " + std::to_string( ( r.pixelInImage - *approximate ).norm() ).substr( 0, 4 ) +
                       " px from the approximate position, beyond the search radius";
          else
            return r;
          if ( regularStart )
          {
            degenerate = degenerate && r.degenerate();
            why = rejected;
          }
          return std::nullopt;
        };
        for ( const Eigen::Vector2d &start : starts )
        {
          const std::optional<LsmResult> lsm = attempt( start, lsmOptions, true );
          if ( lsm && ( !best || lsm->sigma0 < best->sigma0 ) )
            best = lsm;
          // a close fit needs no other start
          if ( best && contrast > 0 && best->sigma0 <= options.goodFitRatio * contrast )
            break;
        }
        // strong scale differences: least squares from the approximate position (or the peak) with the window
        // scaled, when no start gave a plausible match
        for ( const double scale : options.fallbackScales )
        {
          if ( best )
            break;
          LsmOptions scaled = lsmOptions;
          scaled.initialAffine = scale * lsmOptions.initialAffine;
          best = attempt( approximate ? *approximate : result.correlationPixel, scaled, false );
        }
        usedPredicted = best && predicted;
      }
      // matching back lands in the reference within a fraction of a search pixel
      const double consistencyPx = options.consistencyPx / std::min( 1.0, usedPredicted ? smallestScale( *options.predictedShape ) : 1.0 );
      if ( !best && weakPeak )
      {
        result.status = MatchStatus::NoPeak;
        result.message = weakReason + ", and least squares from the approximate position failed: " + why;
        return;
      }
      if ( !best )
      {
        if ( degenerate )
        {
          // a line or an edge: least squares cannot fix the shift along it; the correlation peak stands, at its precision
          correlationOnly( "least-squares matching could not refine: " + why );
          result.lsm.status = LsmResult::Status::Flat;
          result.lsm.message = why;
          return;
        }
        result.status = MatchStatus::Diverged;
        result.message = "least-squares matching failed from every start: " + why;
        result.lsm.status = LsmResult::Status::Diverged;
        result.lsm.message = why;
        return;
      }
      result.lsm = *best;
      result.pixelInImage = best->pixelInImage;
      result.sigmaPx = best->sigmaPxMax();
      if ( options.backMatch )
      {
        // back from the found point to the reference: a right match returns to where it came from
        LsmOptions back = usedPredicted ? adaptedToShape( options.lsmOptions, best->affine.inverse() ) : options.lsmOptions;
        back.initialAffine = best->affine.inverse();
        const LsmResult returned = leastSquaresMatch( search, best->pixelInImage, reference, pixelInReference, back );
        if ( !returned.converged() || ( returned.pixelInImage - pixelInReference ).norm() > consistencyPx )
        {
          result.status = MatchStatus::Inconsistent;
          result.message = returned.converged() ? "matching back returns " + std::to_string( ( returned.pixelInImage - pixelInReference ).norm() ).substr( 0, 4 ) +
                          " px from the reference point" : "matching back does not converge: " + returned.message;
          return;
        }
        // least squares' own sigma takes the residuals for white noise; the closure of the way there and back
        // (in search pixels, two matchings' errors) shows what it leaves out
        const double closurePx = ( best->affine * ( returned.pixelInImage - pixelInReference ) ).norm();
        result.sigmaPx = std::max( result.sigmaPx, closurePx / std::sqrt( 2.0 ) );
      }
      result.status = MatchStatus::Lsm;
    }

    /**
     * In a 2-D search a maximum on the border of the area is no peak: the
     * true one may lie outside. The best candidate inside the area that
     * scores at least as high as each of its neighbours; false if none.
     */
    bool peakInside( const std::vector<std::vector<std::pair<double, const Candidate *>>> &scored, double &best, const Candidate *&bestCandidate, size_t &bestShape )
    {
      best = -2.0;
      bestCandidate = nullptr;
      for ( size_t k = 0; k < scored.size(); ++k )
      {
        std::map<std::pair<int, int>, double> scoreAt;
        for ( const auto &[score, candidate] : scored[k] )
          scoreAt[{ candidate->col, candidate->row }] = score;
        for ( const auto &[score, candidate] : scored[k] )
        {
          if ( candidate->border || score <= best )
            continue;
          bool peak = true;
          for ( int dr = -1; dr <= 1 && peak; ++dr )
            for ( int dc = -1; dc <= 1 && peak; ++dc )
              if ( const auto n = scoreAt.find( { candidate->col + dc, candidate->row + dr } ); ( dc || dr ) && n != scoreAt.end() )
                peak = n->second <= score;
          if ( peak )
          {
            best = score;
            bestCandidate = candidate;
            bestShape = k;
          }
        }
      }
      return bestCandidate != nullptr;
    }

    AreaMatch searchCandidates( const MatchImage &reference, const Eigen::Vector2d &pixelInReference, const MatchImage &search,
                                const std::vector<Candidate> &candidates, const std::optional<Eigen::Vector2d> &approximate, double radiusPx,
                                const AreaMatchOptions &options, bool jumps )
    {
      AreaMatch result;
      if ( !reference.canSample( pixelInReference.x(), pixelInReference.y() ) )
      {
        result.status = MatchStatus::Outside;
        result.message = "the point lies outside the reference image";
        return result;
      }
      const int centreCol = static_cast<int>( std::floor( pixelInReference.x() ) ), centreRow = static_cast<int>( std::floor( pixelInReference.y() ) );
      const CorrelationTemplate square( reference, centreCol, centreRow, options.windowWidth, options.windowHeight, options.measure );
      if ( !square.valid() )
      {
        result.status = square.flat() ? MatchStatus::NoPeak : MatchStatus::Outside;
        result.message = square.reason();
        return result;
      }
      if ( candidates.empty() )
      {
        result.status = MatchStatus::Outside;
        result.message = "no search position in the search image";
        return result;
      }
      // the square window (the template is centred on the reference pixel's centre: the point's offset from it is
      // carried over) and, when the geometry predicts one, the reference patch in the search image's shape
      std::vector<WindowShape> shapes { { &square, Eigen::Matrix2d::Identity(), pixelInReference - Eigen::Vector2d( centreCol + 0.5, centreRow + 0.5 ) } };
      std::optional<CorrelationTemplate> shaped;
      if ( options.predictedShape && std::abs( options.predictedShape->determinant() ) > 1e-9 )
      {
        shaped.emplace( reference, pixelInReference, options.predictedShape->inverse(), options.windowWidth, options.windowHeight, options.measure );
        if ( shaped->valid() )
          shapes.push_back( { &*shaped, *options.predictedShape, Eigen::Vector2d::Zero() } );
      }
      double best = -2.0;
      const Candidate *bestCandidate = nullptr;
      size_t bestShape = 0;
      std::vector<std::vector<std::pair<double, const Candidate *>>> scored( shapes.size() );
      for ( size_t k = 0; k < shapes.size(); ++k )
      {
        int skipUntil = -1;
        for ( const Candidate &candidate : candidates )
        {
          if ( jumps && candidate.along < skipUntil )
            continue;
          const std::optional<double> score = shapes[k].target->score( search, candidate.col, candidate.row );
          ++result.candidates;
          if ( !score )
            continue;
          scored[k].emplace_back( *score, &candidate );
          if ( *score > best )
          {
            best = *score;
            bestCandidate = &candidate;
            bestShape = k;
          }
          if ( jumps )
            skipUntil = candidate.along + ( *score < 0.2 ? 4 : *score < 0.4 ? 3 : *score < 0.6 ? 2 : 0 );
        }
      }
      if ( !bestCandidate )
      {
        result.status = MatchStatus::Outside;
        result.message = "every search window leaves the search image or is flat";
        return result;
      }
      bool peakInArea = true;
      if ( options.borderIsNoPeak && std::any_of( candidates.begin(), candidates.end(), []( const Candidate &c ) { return c.border; } ) )
      {
        double inside = -2.0;
        const Candidate *insideCandidate = nullptr;
        size_t insideShape = 0;
        peakInArea = peakInside( scored, inside, insideCandidate, insideShape );
        if ( peakInArea )
        {
          best = inside;
          bestCandidate = insideCandidate;
          bestShape = insideShape;
        }
      }
      const WindowShape &shape = shapes[bestShape];
      result.shapedWindow = bestShape > 0;
      result.score = best;
      // the best score of a separate peak: more than 2 px from the best
      std::vector<std::pair<double, const Candidate *>> &winner = scored[bestShape];
      for ( const auto &[score, candidate] : winner )
        if ( std::hypot( candidate->col - bestCandidate->col, candidate->row - bestCandidate->row ) > 2.5 )
          result.secondScore = std::max( result.secondScore, score );
      // the separate peaks, best first (greedy: a candidate joins when no better one is within 2.5 px)
      std::sort( winner.begin(), winner.end(), []( const auto &a, const auto &b ) { return a.first > b.first; } );
      for ( const auto &[score, candidate] : winner )
      {
        const Eigen::Vector2d at( candidate->col + 0.5, candidate->row + 0.5 );
        bool separate = true;
        for ( const auto &peak : result.peaks )
          separate = separate && ( peak.first - shape.offset - at ).norm() > 2.5;
        if ( separate )
          result.peaks.emplace_back( at + shape.offset, score );
        if ( result.peaks.size() >= 8 )
          break;
      }
      refine( reference, pixelInReference, search, shape, bestCandidate->col, bestCandidate->row, peakInArea, approximate, radiusPx, options, result );
      return result;
    }
  }

  void AreaMatchOptions::check() const
  {
    const auto odd = []( int w, int h ) { return w >= 1 && h >= 1 && w % 2 == 1 && h % 2 == 1 && w <= 101 && h <= 101; };
    if ( !odd( windowWidth, windowHeight ) || ( lsm && !odd( lsmOptions.windowWidth, lsmOptions.windowHeight ) ) )
      throw std::invalid_argument( "The window sizes must be odd (the point sits in the centre pixel) and at most 101 pixels." );
    if ( lsm )
      lsmOptions.check();
    if ( !( minScore >= -1.0 && minScore <= 1.0 ) )
      throw std::invalid_argument( "The minimum correlation must lie between -1 and 1." );
    if ( bandHalfWidthPx < 0 )
      throw std::invalid_argument( "The epipolar band cannot have a negative width." );
  }

  std::string matchStatusName( MatchStatus status )
  {
    switch ( status )
    {
      case MatchStatus::Lsm:
        return "lsm";
      case MatchStatus::Correlation:
        return "correlation";
      case MatchStatus::NoPeak:
        return "no_peak";
      case MatchStatus::Ambiguous:
        return "ambiguous";
      case MatchStatus::Diverged:
        return "diverged";
      case MatchStatus::Inconsistent:
        return "inconsistent";
      case MatchStatus::Outside:
        return "outside";
    }
    return "no_peak";
  }

  AreaMatch matchAlongEpipolarBand( const MatchImage &reference, const Eigen::Vector2d &pixelInReference, const MatchImage &search,
                                    const std::vector<Eigen::Vector2d> &curve, const AreaMatchOptions &options )
  {
    return searchCandidates( reference, pixelInReference, search, bandCandidates( curve, std::max( 0, options.bandHalfWidthPx ), search.width(), search.height() ),
                             std::nullopt, 0.0, options, options.jumpRule );
  }

  AreaMatch matchAroundPosition( const MatchImage &reference, const Eigen::Vector2d &pixelInReference, const MatchImage &search,
                                 const Eigen::Vector2d &approximate, double radiusPx, const AreaMatchOptions &options )
  {
    std::vector<Candidate> candidates;
    const int r = static_cast<int>( std::ceil( radiusPx ) );
    const int c0 = static_cast<int>( std::floor( approximate.x() ) ), r0 = static_cast<int>( std::floor( approximate.y() ) );
    const auto inside = [&]( int dc, int dr ) { return dc * dc + dr * dr <= radiusPx * radiusPx + 1e-9; };
    for ( int dr = -r; dr <= r; ++dr )
      for ( int dc = -r; dc <= r; ++dc )
        if ( inside( dc, dr ) )
        {
          bool border = false;
          for ( int er = -1; er <= 1; ++er )
            for ( int ec = -1; ec <= 1; ++ec )
              border = border || !inside( dc + ec, dr + er );
          candidates.push_back( { c0 + dc, r0 + dr, 0, border } );
        }
    return searchCandidates( reference, pixelInReference, search, candidates, approximate, radiusPx, options, false );
  }

} // namespace geostation
