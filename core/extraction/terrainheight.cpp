/***************************************************************************
  terrainheight.cpp - the mean terrain height of an oriented pair (terrainheight.h)
 ***************************************************************************/
#include "extraction/terrainheight.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <vector>

#include "adjustment/intersection.h"
#include "geometry/epipolar.h"
#include "matching/areamatcher.h"
#include "matching/matchingwindows.h"

namespace geostation
{
  namespace
  {
    constexpr int kGrid = 9;
    constexpr int kMinPoints = 5;
    constexpr double kVoteScore = 0.6;     //!< a correlation peak this good votes
    constexpr double kBandFraction = 0.02; //!< the band's half width, of the height of A's camera above it
    constexpr double kBandParallaxPx = 4.0; //!< ... and at least this much parallax
    constexpr double kRunnerUpShare = 0.75; //!< another band shared by this share of the points as many: no height can be told

    //! A height one grid point's correlation peak stands for, and how wide the band around it is.
    struct Vote
    {
      double heightM = 0.0;
      double toleranceM = 0.0;
      int point = 0;
      double score = 0.0;
    };

    AreaMatchOptions gridMatchOptions()
    {
      AreaMatchOptions match;
      match.windowWidth = match.windowHeight = 21;
      match.minScore = 0.7;
      return match;
    }

    //! The pixels of `p`'s epipolar curve in B, in the frame, between two distances along A's ray.
    std::vector<Eigen::Vector2d> bandOf( const OrientedImage &a, const OrientedImage &b, const Eigen::Vector2d &p, double minM, double maxM )
    {
      EpipolarOptions epipolar;
      epipolar.minDistanceM = minM;
      epipolar.maxDistanceM = maxM;
      epipolar.maxSegmentPx = 1.0;
      std::vector<Eigen::Vector2d> band;
      for ( const auto &piece : epipolarCurve( a, p, b, epipolar ).pieces )
        for ( const EpipolarVertex &v : piece )
          if ( v.inFrame )
            band.push_back( v.pixelInImage );
      return band;
    }

    std::optional<double> heightOf( const OrientedImage &a, const OrientedImage &b, const Eigen::Vector2d &p, const Eigen::Vector2d &q )
    {
      const IntersectionSummary x = intersectRays( { { &a, p, 0.5 }, { &b, q, 0.5 } } );
      return x.ok() ? std::optional<double>( x.point.z() ) : std::nullopt;
    }

    //! The grid point `p`'s separate correlation peaks along its whole curve, as heights with their bands.
    void voteAlongTheCurve( const OrientedImage &a, const OrientedImage &b, PairMatchWindows &images, const Eigen::Vector2d &p, int point, std::vector<Vote> &votes )
    {
      const std::vector<Eigen::Vector2d> band = bandOf( a, b, p, 1.0, 100000.0 );
      if ( band.size() < 3 )
        return;
      AreaMatchOptions correlation = gridMatchOptions();
      correlation.lsm = false;
      // the curve may cross the whole partner: its window is cut to the part around the curve's middle past this
      const MatchImage &imageA = images.holding( 0, matchingWindowAround( p, 0.0, correlation, images.size( 0 ) ), 0 );
      const MatchImage &imageB = images.holding( 1, matchingWindowAlong( band, correlation, images.size( 1 ), 16LL << 20 ), 0 );
      const AreaMatch m = matchAlongEpipolarBand( imageA, p, imageB, band, correlation );
      for ( const auto &[q, score] : m.peaks )
      {
        if ( score < kVoteScore )
          continue;
        const std::optional<double> z = heightOf( a, b, p, q );
        if ( !z )
          continue;
        // the band: a share of the camera's height above it, and at least a few pixels of parallax along the curve
        size_t k = 0;
        for ( size_t i = 1; i < band.size(); ++i )
          if ( ( band[i] - q ).squaredNorm() < ( band[k] - q ).squaredNorm() )
            k = i;
        const Eigen::Vector2d along = ( band[std::min( k + 1, band.size() - 1 )] - band[k > 0 ? k - 1 : 0] ).normalized();
        const std::optional<double> shifted = heightOf( a, b, p, q + kBandParallaxPx * along );
        const double above = a.exterior().projectionCentre.z() - *z;
        votes.push_back( { *z, std::max( { kBandFraction * std::abs( above ), shifted ? std::abs( *shifted - *z ) : 0.0, 0.5 } ), point, score } );
      }
    }

    //! A band of heights around a vote and the grid points with a vote in it.
    struct SharedBand
    {
      const Vote *centre = nullptr;
      int points = 0;
      double score = 0.0;
    };

    SharedBand bandAround( const Vote &centre, const std::vector<Vote> &votes )
    {
      std::set<int> points;
      SharedBand band { &centre, 0, 0.0 };
      for ( const Vote &v : votes )
        if ( std::abs( v.heightM - centre.heightM ) <= centre.toleranceM && points.insert( v.point ).second )
          band.score += v.score;
      band.points = static_cast<int>( points.size() );
      return band;
    }

    bool better( const SharedBand &a, const SharedBand &b ) { return a.points > b.points || ( a.points == b.points && a.score > b.score ); }

    /**
     * The band most grid points share (ties: the better correlation), and
     * the best band apart from it: on a texture that repeats the same way
     * everywhere an alias is shared as widely, and then no height can be told.
     */
    std::pair<SharedBand, SharedBand> sharedBands( const std::vector<Vote> &votes )
    {
      std::vector<SharedBand> bands;
      for ( const Vote &centre : votes )
        bands.push_back( bandAround( centre, votes ) );
      SharedBand best, runnerUp;
      for ( const SharedBand &band : bands )
        if ( better( band, best ) )
          best = band;
      for ( const SharedBand &band : bands )
        if ( best.centre && std::abs( band.centre->heightM - best.centre->heightM ) > best.centre->toleranceM + band.centre->toleranceM && better( band, runnerUp ) )
          runnerUp = band;
      return { best, runnerUp };
    }

    //! Each grid point's best-correlated vote within the band around `centre`: one height per point.
    std::vector<double> votedHeights( const std::vector<Vote> &votes, const Vote &centre )
    {
      std::map<int, const Vote *> best;
      for ( const Vote &v : votes )
        if ( std::abs( v.heightM - centre.heightM ) <= centre.toleranceM && ( !best.count( v.point ) || v.score > best[v.point]->score ) )
          best[v.point] = &v;
      std::vector<double> heights;
      for ( const auto &[point, vote] : best )
        heights.push_back( vote->heightM );
      return heights;
    }

    //! `p` matched by least squares where its curve crosses the heights [lowM, highM]; its height, if unambiguous.
    std::optional<double> heightWithinBand( const OrientedImage &a, const OrientedImage &b, PairMatchWindows &images, const Eigen::Vector2d &p, double lowM,
                                            double highM )
    {
      const std::optional<Ray> ray = a.worldRayFromPixel( p );
      if ( !ray || !( ray->direction.z() < -1e-6 ) )
        return std::nullopt;
      const double toHigh = ( highM - ray->origin.z() ) / ray->direction.z(), toLow = ( lowM - ray->origin.z() ) / ray->direction.z();
      if ( !( toLow > 1.0 ) )
        return std::nullopt;
      const std::vector<Eigen::Vector2d> band = bandOf( a, b, p, std::max( 1.0, toHigh ), toLow );
      if ( band.size() < 3 )
        return std::nullopt;
      const AreaMatchOptions match = gridMatchOptions();
      const MatchImage &imageA = images.holding( 0, matchingWindowAround( p, 0.0, match, images.size( 0 ) ), 0 );
      const MatchImage &imageB = images.holding( 1, matchingWindowAlong( band, match, images.size( 1 ), 16LL << 20 ), 0 );
      const AreaMatch m = matchAlongEpipolarBand( imageA, p, imageB, band, match );
      if ( m.status != MatchStatus::Lsm || m.secondScore > m.score - match.ambiguityMargin )
        return std::nullopt;
      return heightOf( a, b, p, m.pixelInImage );
    }
  } // namespace

  TerrainHeightEstimate estimateTerrainHeight( const OrientedImage &a, const OrientedImage &b, const MatchImage &imageA, const MatchImage &imageB )
  {
    PairMatchWindows images( imageA, imageB );
    return estimateTerrainHeight( a, b, images );
  }

  TerrainHeightEstimate estimateTerrainHeight( const OrientedImage &a, const OrientedImage &b, PairMatchWindows &images )
  {
    using Status = TerrainHeightEstimate::Status;
    const auto fail = []( Status status, const std::string &why )
    {
      TerrainHeightEstimate none;
      none.status = status;
      none.message = why;
      return none;
    };
    if ( !images.available() )
      return fail( Status::Unreadable, "the images cannot be read for matching" );
    std::vector<Eigen::Vector2d> grid;
    for ( int r = 1; r <= kGrid; ++r )
      for ( int c = 1; c <= kGrid; ++c )
        grid.emplace_back( images.size( 0 ).width * c / ( kGrid + 1.0 ), images.size( 0 ).height * r / ( kGrid + 1.0 ) );

    // 1. the votes of every grid point's correlation peaks along its whole curve; the band most of them share
    std::vector<Vote> votes;
    for ( size_t i = 0; i < grid.size(); ++i )
      voteAlongTheCurve( a, b, images, grid[i], static_cast<int>( i ), votes );
    std::set<int> voting;
    for ( const Vote &v : votes )
      voting.insert( v.point );
    const auto [best, runnerUp] = sharedBands( votes );
    const Vote *band = best.centre;
    const int shared = best.points;
    if ( !band || shared < kMinPoints )
      return fail( Status::NoSharedHeight, std::to_string( voting.size() ) + " of the " + std::to_string( grid.size() ) + " grid points found a correlation peak above " +
                   std::to_string( kVoteScore ).substr( 0, 3 ) + " along their epipolar curves, and no terrain height is shared by " + std::to_string( kMinPoints ) +
                   " of them (the images do not overlap, or have too little texture)" );

    if ( runnerUp.centre && runnerUp.points >= kRunnerUpShare * shared )
      return fail( Status::RepeatingTexture, "the texture repeats: terrain heights of about " + std::to_string( static_cast<int>( std::lround( band->heightM ) ) ) + " m and " +
                   std::to_string( static_cast<int>( std::lround( runnerUp.centre->heightM ) ) ) + " m are shared by " + std::to_string( shared ) + " and " +
                   std::to_string( runnerUp.points ) + " grid points" );

    // 2. each grid point matched by least squares within that band
    const double halfWidth = 2.0 * band->toleranceM;
    std::vector<double> heights;
    for ( const Eigen::Vector2d &p : grid )
      if ( const std::optional<double> z = heightWithinBand( a, b, images, p, band->heightM - halfWidth, band->heightM + halfWidth ) )
        heights.push_back( *z );
    TerrainHeightEstimate e;
    e.votingPoints = shared;
    e.byLeastSquares = static_cast<int>( heights.size() ) >= kMinPoints;
    if ( !e.byLeastSquares )
    {
      // fields of one grey each with a fine texture: few points match by least squares without a second peak
      // within the band, but their correlation peaks agree on it; each point's best peak in the band is its height
      heights = votedHeights( votes, *band );
      if ( static_cast<int>( heights.size() ) < kMinPoints )
        return fail( Status::NoUniqueMatch, std::to_string( shared ) + " grid points agree on a terrain height of about " + std::to_string( static_cast<int>( std::lround( band->heightM ) ) ) +
                     " m, but only " + std::to_string( heights.size() ) + " of them match by least squares without a second peak there" );
    }
    std::sort( heights.begin(), heights.end() );
    e.heightM = heights[heights.size() / 2];
    e.points = static_cast<int>( heights.size() );
    std::vector<double> deviations;
    for ( double h : heights )
      deviations.push_back( std::abs( h - e.heightM ) );
    std::sort( deviations.begin(), deviations.end() );
    e.spreadM = deviations[deviations.size() / 2];
    return e;
  }

} // namespace geostation
