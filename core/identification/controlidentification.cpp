/***************************************************************************
  controlidentification.cpp - which image point is which control point
 ***************************************************************************/
#include "identification/controlidentification.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cmath>
#include <set>
#include <stdexcept>

#include "geometry/projection.h"
#include "geometry/rotation.h"
#include "identification/falsealarms.h"
#include "identification/posehypotheses.h"

namespace geostation
{

  void ControlIdentificationOptions::check() const
  {
    if ( neighboursOnGround < 2 || neighboursInImage < 2 || candidatesForHypotheses < 3 )
      throw std::invalid_argument( "a triangle needs at least two neighbours on the ground and in the image" );
    if ( !( maxForeshortening >= 1.0 ) )
      throw std::invalid_argument( "the largest foreshortening must be at least 1" );
    if ( !( hypothesisTolerancePx > 0.0 ) || !( tolerancePx > 0.0 ) )
      throw std::invalid_argument( "the matching tolerances must be positive" );
    if ( minPairs < 4 )
      throw std::invalid_argument( "an identification needs at least 4 pairs (the resection's 6 unknowns and a check)" );
    if ( !( maxFalseAlarms > 0.0 ) || !( densityRadiusPx > tolerancePx ) )
      throw std::invalid_argument( "the false alarms allowed must be positive and the density radius larger than the tolerance" );
    if ( runnerUpMargin < 0 || hypothesesVerified < 1 )
      throw std::invalid_argument( "the runner-up margin must not be negative and at least one hypothesis must be verified" );
    if ( !( candidateSigmaPx > 0.0 ) )
      throw std::invalid_argument( "the candidates' sigma must be positive" );
    if ( approximate && !( searchRadiusPx > 0.0 ) )
      throw std::invalid_argument( "the search radius around the approximate orientation must be positive" );
  }

  namespace
  {
    //! ControlPairs of an oriented image (pixels, with the lens), and the control in the frame without a candidate.
    ControlPairs pairsOfOrientation( const OrientedImage &oriented, const std::vector<ControlPoint> &control, const std::vector<Eigen::Vector2d> &candidatesPx,
                              double tolerancePx, std::vector<PredictedControl> *notFound )
    {
      std::vector<std::tuple<double, int, int>> proposals;
      std::vector<std::pair<int, Eigen::Vector2d>> inFrame;
      for ( int j = 0; j < static_cast<int>( control.size() ); ++j )
      {
        const GroundProjection g = oriented.projectGroundToPixel( control[j].world );
        if ( !g.ok() )
          continue;
        if ( g.inFrame )
          inFrame.emplace_back( j, g.pixelInImage );
        for ( int i = 0; i < static_cast<int>( candidatesPx.size() ); ++i )
        {
          const double d = ( candidatesPx[i] - g.pixelInImage ).norm();
          if ( d <= tolerancePx )
            proposals.emplace_back( d, j, i );
        }
      }
      ControlPairs pairs = matchOneToOne( std::move( proposals ) );
      if ( notFound )
        for ( const auto &[j, pixel] : inFrame )
          if ( std::none_of( pairs.begin(), pairs.end(), [j = j]( const std::pair<int, int> &p ) { return p.first == j; } ) )
            notFound->push_back( { control[j].id, pixel } );
      return pairs;
    }

    ExteriorOrientation exteriorOf( const ThreePointPose &pose, const Eigen::Vector3d &origin )
    {
      return ExteriorOrientation::fromCentreAndRotation( pose.centre + origin, pose.cameraFromWorld.transpose() );
    }

    struct Verified
    {
      ControlPairs pairs;       //!< after the last resection, blunders removed
      std::vector<std::string> blunders;
      ResectionSummary resection;
      double falseAlarms = 0.0;
    };

    /**
     * The resection loop from a hypothesis: resect on its pairs, project all
     * control, match within the tolerance, until the pairs stay the same.
     */
    std::optional<Verified> verify( const Camera &camera, const std::vector<ControlPoint> &control, const std::vector<Eigen::Vector2d> &candidatesPx,
                                    ControlPairs pairs, ExteriorOrientation start, const ControlIdentificationOptions &options )
    {
      ResectionOptions resectionOptions = options.resection;
      resectionOptions.robust = true;
      resectionOptions.removeBlunders = true;
      for ( int round = 0; round < 6; ++round )
      {
        if ( static_cast<int>( pairs.size() ) < 4 )
          return std::nullopt;
        std::vector<ControlPoint> used;
        std::vector<ImagePoint> observed;
        for ( const auto &[j, i] : pairs )
        {
          ControlPoint c = control[j];
          c.check = false;
          used.push_back( c );
          observed.push_back( { c.id, candidatesPx[i], options.candidateSigmaPx } );
        }
        resectionOptions.initial = start;
        ResectionSummary resection = resectImage( camera, used, observed, resectionOptions );
        if ( !resection.ok() )
          return std::nullopt;
        ControlPairs kept;
        for ( const auto &[j, i] : pairs )
          if ( std::find( resection.blunders.begin(), resection.blunders.end(), control[j].id ) == resection.blunders.end() )
            kept.emplace_back( j, i );
        start = resection.exterior;
        const ControlPairs again = pairsOfOrientation( OrientedImage( camera, resection.exterior ), control, candidatesPx, options.tolerancePx, nullptr );
        if ( again == kept || round == 5 )
          return Verified { kept, resection.blunders, std::move( resection ), 0.0 };
        pairs = again;
      }
      return std::nullopt;
    }

    std::string formatChance( double n )
    {
      char text[32];
      std::snprintf( text, sizeof text, n < 0.01 || n >= 1000 ? "%.1e" : "%.2f", n );
      return text;
    }

    int shared( const ControlPairs &a, const ControlPairs &b )
    {
      int n = 0;
      for ( const auto &p : a )
        n += std::binary_search( b.begin(), b.end(), p ) ? 1 : 0;
      return n;
    }

    //! Throws std::invalid_argument on a camera, options, control or candidates that cannot be used.
    void checkInputs( const Camera &camera, const std::vector<ControlPoint> &control, const std::vector<Eigen::Vector2d> &candidatesPx, const ControlIdentificationOptions &options )
    {
      camera.validate();
      options.check();
      std::set<std::string> ids;
      for ( const ControlPoint &c : control )
      {
        if ( !c.world.allFinite() )
          throw std::invalid_argument( "control point " + c.id + " has no finite coordinates" );
        if ( !ids.insert( c.id ).second )
          throw std::invalid_argument( "control point " + c.id + " is listed twice" );
      }
      for ( const Eigen::Vector2d &p : candidatesPx )
        if ( !p.allFinite() )
          throw std::invalid_argument( "a candidate has no finite position" );
    }

    //! The control points a search may pair, and (with an approximate orientation) each one's candidates.
    struct EligibleControl
    {
      std::vector<int> eligible;             //!< indices into the control
      std::vector<std::vector<int>> allowed; //!< per control point, the candidates near its prediction; empty: any
    };

    /**
     * Without an approximate orientation every control point; with one, those
     * whose prediction has a candidate within the search radius, with those candidates.
     */
    EligibleControl eligibleControl( const Camera &camera, const std::vector<ControlPoint> &control, const std::vector<Eigen::Vector2d> &usablePx,
                                     const ControlIdentificationOptions &options )
    {
      EligibleControl out;
      if ( !options.approximate )
      {
        for ( int j = 0; j < static_cast<int>( control.size() ); ++j )
          out.eligible.push_back( j );
        return out;
      }
      out.allowed.resize( control.size() );
      const OrientedImage approximate( camera, *options.approximate );
      for ( int j = 0; j < static_cast<int>( control.size() ); ++j )
      {
        const GroundProjection g = approximate.projectGroundToPixel( control[j].world );
        if ( !g.ok() )
          continue;
        for ( int k = 0; k < static_cast<int>( usablePx.size() ); ++k )
          if ( ( usablePx[k] - g.pixelInImage ).norm() <= options.searchRadiusPx )
            out.allowed[j].push_back( k );
        if ( !out.allowed[j].empty() )
          out.eligible.push_back( j );
      }
      return out;
    }

    //! What a match on each candidate is worth: -log of the chance of landing on it, from the candidates around it.
    std::vector<double> candidateWorth( const std::vector<Eigen::Vector2d> &usablePx, const ControlIdentificationOptions &options )
    {
      std::vector<double> worth( usablePx.size() );
      for ( size_t k = 0; k < usablePx.size(); ++k )
      {
        int near = 0;
        for ( size_t m = 0; m < usablePx.size(); ++m )
          near += ( m != k && ( usablePx[m] - usablePx[k] ).norm() <= options.densityRadiusPx ) ? 1 : 0;
        const double chance = ( near + 1.0 ) * options.hypothesisTolerancePx * options.hypothesisTolerancePx / ( options.densityRadiusPx * options.densityRadiusPx );
        worth[k] = -std::log( std::min( 0.5, chance ) );
      }
      return worth;
    }

    //! How often chance would give a verified identification as good, over `tests` poses tested (the a-contrario test).
    double falseAlarmsOf( const Verified &v, const Camera &camera, const std::vector<ControlPoint> &control, const std::vector<Eigen::Vector2d> &usablePx,
                          const ControlIdentificationOptions &options, double tests )
    {
      const OrientedImage oriented( camera, v.resection.exterior );
      std::vector<Eigen::Vector2d> predicted;
      for ( const ControlPoint &c : control )
      {
        const GroundProjection g = oriented.projectGroundToPixel( c.world );
        if ( g.ok() && g.inFrame )
          predicted.push_back( g.pixelInImage );
      }
      std::vector<double> residuals;
      for ( const auto &[j, i] : v.pairs )
      {
        const GroundProjection g = oriented.projectGroundToPixel( control[j].world );
        residuals.push_back( g.ok() ? ( g.pixelInImage - usablePx[i] ).norm() : 1e300 );
      }
      return identificationFalseAlarms( predicted, usablePx, residuals, options.tolerancePx, options.densityRadiusPx, tests );
    }
  } // namespace

  ControlIdentificationSummary identifyControl( const Camera &camera, const std::vector<ControlPoint> &control, const std::vector<Eigen::Vector2d> &candidatesPx,
      const ControlIdentificationOptions &options )
  {
    const auto started = std::chrono::steady_clock::now();
    checkInputs( camera, control, candidatesPx, options );

    ControlIdentificationSummary summary;
    auto finish = [&]( ControlIdentificationSummary::Status status, const std::string &message ) {
      summary.status = status;
      summary.message = message;
      summary.seconds = std::chrono::duration<double>( std::chrono::steady_clock::now() - started ).count();
      return summary;
    };

    // candidates as ideal rays (strongest first, as given); the control relative to its centroid
    std::vector<Eigen::Vector2d> ideal, usablePx;
    std::vector<int> usable;
    for ( int i = 0; i < static_cast<int>( candidatesPx.size() ); ++i )
      if ( const std::optional<Eigen::Vector3d> ray = camera.rayInCameraFromPixel( candidatesPx[i] ) )
      {
        ideal.push_back( ray->head<2>() );
        usablePx.push_back( candidatesPx[i] );
        usable.push_back( i );
      }
    const int needed = std::max( 3, options.minPairs );
    if ( static_cast<int>( ideal.size() ) < needed )
      return finish( ControlIdentificationSummary::Status::TooFewCandidates,
                     "only " + std::to_string( ideal.size() ) + " candidates were found in the image; at least " + std::to_string( needed ) + " are needed" );
    Eigen::Vector3d origin = Eigen::Vector3d::Zero();
    for ( const ControlPoint &c : control )
      origin += c.world / static_cast<double>( std::max<size_t>( 1, control.size() ) );
    std::vector<Eigen::Vector3d> local;
    for ( const ControlPoint &c : control )
      local.push_back( c.world - origin );

    const EligibleControl near = eligibleControl( camera, control, usablePx, options );
    const std::vector<int> &eligible = near.eligible;
    if ( static_cast<int>( eligible.size() ) < options.minPairs )
      return finish( ControlIdentificationSummary::Status::TooFewControl,
                     options.approximate ? "only " + std::to_string( eligible.size() ) + " control points have a candidate within " + std::to_string( static_cast<int>( options.searchRadiusPx ) ) +
                     " px of where the approximate orientation puts them; at least " + std::to_string( options.minPairs ) + " are needed"
                     : "only " + std::to_string( control.size() ) + " control points were given; at least " + std::to_string( options.minPairs ) + " are needed" );

    const std::vector<double> worth = candidateWorth( usablePx, options );
    // triangles in the image among the strongest candidates (all near the prediction with an approximate orientation)
    std::vector<int> firsts;
    for ( int k = 0; k < static_cast<int>( ideal.size() ); ++k )
      if ( options.approximate || k < options.candidatesForHypotheses )
        firsts.push_back( k );
    PoseHypothesisOptions hypothesisOptions;
    hypothesisOptions.neighboursOnGround = options.neighboursOnGround;
    hypothesisOptions.neighboursInImage = options.neighboursInImage;
    hypothesisOptions.maxForeshortening = options.maxForeshortening;
    hypothesisOptions.tolerance = options.hypothesisTolerancePx / camera.fx();
    hypothesisOptions.minSideIdeal = 2.0 / camera.fx();
    hypothesisOptions.kept = static_cast<size_t>( options.hypothesesVerified ) * 16;
    PoseHypotheses hypotheses( local, ideal, worth, eligible, firsts, near.allowed, hypothesisOptions );

    // strongest candidates first; at checkpoints (after 6, 12, 24, ... and all) the best hypotheses are
    // verified, and the search stops at an identification chance cannot explain
    std::vector<Verified> solutions;
    std::vector<ControlPairs> tried;
    int looks = 0;
    auto accepted = [&]() {
      ++looks;
      for ( const PoseHypothesis &h : hypotheses.best() )
      {
        if ( static_cast<int>( tried.size() ) >= options.hypothesesVerified * looks )
          break;
        const ControlPairs pairs = hypotheses.pairsOf( h.pose );
        if ( std::any_of( tried.begin(), tried.end(), [&]( const ControlPairs &t ) { return 2 * shared( pairs, t ) > static_cast<int>( pairs.size() ); } ) )
          continue;
        tried.push_back( pairs );
        if ( options.progress.stopRequested() )
          break;
        if ( std::optional<Verified> v = verify( camera, control, usablePx, pairs, exteriorOf( h.pose, origin ), options ) )
          solutions.push_back( std::move( *v ) );
      }
      summary.hypothesesVerified = static_cast<int>( tried.size() );
      // tested so far: the poses scored, at every look
      for ( Verified &v : solutions )
        v.falseAlarms = falseAlarmsOf( v, camera, control, usablePx, options, static_cast<double>( looks ) * static_cast<double>( hypotheses.poses() ) );
      std::vector<const Verified *> good;
      for ( const Verified &v : solutions )
        if ( v.falseAlarms <= options.maxFalseAlarms && static_cast<int>( v.pairs.size() ) >= options.minPairs )
          good.push_back( &v );
      std::sort( good.begin(), good.end(), []( const Verified *a, const Verified *b ) {
        return a->pairs.size() != b->pairs.size() ? a->pairs.size() > b->pairs.size() : a->resection.rmseControlPx < b->resection.rmseControlPx;
      } );
      return good;
    };
    std::vector<const Verified *> good;
    for ( size_t n = 0, checkpoint = 6; n < firsts.size(); ++n )
    {
      if ( !options.progress.report( static_cast<double>( n ) / firsts.size(), "candidate " + std::to_string( n + 1 ) + " of " + std::to_string( firsts.size() ) ) )
        return finish( ControlIdentificationSummary::Status::Cancelled, "the identification was cancelled after " + std::to_string( n ) + " candidates" );
      hypotheses.addFrom( firsts[n] );
      if ( n + 1 < firsts.size() && n + 1 != checkpoint )
        continue;
      checkpoint *= 2;
      good = accepted();
      if ( !good.empty() )
      {
        int runnerUp = 0;
        for ( size_t s = 1; s < good.size() && !runnerUp; ++s )
          if ( 2 * shared( good[s]->pairs, good.front()->pairs ) <= static_cast<int>( good[s]->pairs.size() ) )
            runnerUp = static_cast<int>( good[s]->pairs.size() );
        if ( runnerUp + options.runnerUpMargin <= static_cast<int>( good.front()->pairs.size() ) )
          break; // clear enough: the rest of the search could only add tests
      }
    }
    summary.triangles = hypotheses.triangles();
    summary.poses = hypotheses.poses();
    if ( options.progress.stopRequested() )
      return finish( ControlIdentificationSummary::Status::Cancelled, "the identification was cancelled while verifying its hypotheses" );
    if ( good.empty() )
    {
      double bestChance = 1e300;
      for ( const Verified &v : solutions )
        bestChance = std::min( bestChance, v.falseAlarms );
      return finish( ControlIdentificationSummary::Status::NotFound,
                     "no arrangement of the " + std::to_string( ideal.size() ) + " candidates matches at least " + std::to_string( options.minPairs ) +
                     " control points with an orientation that chance cannot explain (" + std::to_string( summary.poses ) + " poses tried, " +
                     std::to_string( solutions.size() ) + " verified" + ( solutions.empty() ? "" : ", the best expected by chance " + formatChance( bestChance ) + " times" ) + ")" );
    }
    const Verified &winner = *good.front();
    summary.falseAlarms = winner.falseAlarms;
    for ( size_t s = 1; s < good.size(); ++s )
      if ( 2 * shared( good[s]->pairs, winner.pairs ) <= static_cast<int>( good[s]->pairs.size() ) )
      {
        summary.runnerUpPairs = static_cast<int>( good[s]->pairs.size() );
        break;
      }
    summary.resection = winner.resection;
    summary.rejected = winner.blunders;
    const OrientedImage oriented( camera, winner.resection.exterior );
    for ( const auto &[j, i] : winner.pairs )
    {
      IdentifiedControl id;
      id.pointId = control[j].id;
      id.candidate = usable[i];
      id.pixelInImage = usablePx[i];
      const GroundProjection g = oriented.projectGroundToPixel( control[j].world );
      id.residualPx = g.ok() ? Eigen::Vector2d( g.pixelInImage - usablePx[i] ) : Eigen::Vector2d::Zero();
      summary.identified.push_back( id );
    }
    pairsOfOrientation( oriented, control, usablePx, options.tolerancePx, &summary.notFound );
    if ( summary.runnerUpPairs + options.runnerUpMargin > static_cast<int>( winner.pairs.size() ) )
      return finish( ControlIdentificationSummary::Status::Ambiguous,
                     "two different identifications fit almost equally well (" + std::to_string( winner.pairs.size() ) + " and " + std::to_string( summary.runnerUpPairs ) +
                     " pairs); measure two points by hand or give an approximate orientation" );
    return finish( ControlIdentificationSummary::Status::Ok, std::to_string( winner.pairs.size() ) + " control points identified" );
  }

} // namespace geostation
