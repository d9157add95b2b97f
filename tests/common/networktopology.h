// The topology of an extracted road network against the truth graph: the
// average path-length similarity (APLS, as the SpaceNet road challenge
// scores networks). Both networks become graphs - polylines sampled every
// few pixels, nodes where lines cross, and a line's open end joined to a
// line it stops short of within a snapping distance (the truth's centre
// lines end at the other road's edge, not at its centre line). Control
// points are taken along one graph and snapped to the other; for every pair
// of control points the shortest path lengths in both graphs are compared:
//   term = min(1, |L_from - L_to| / L_from), 1 when the pair is not
//   connected (or a point not found) in the other graph,
//   similarity = 1 - mean(term).
// Truth -> result penalises gaps and missing roads (a broken junction makes
// paths long or impossible); result -> truth penalises false roads and false
// connections. APLS is the harmonic mean of the two.
#ifndef GEOSTATION_TESTS_NETWORKTOPOLOGY_H
#define GEOSTATION_TESTS_NETWORKTOPOLOGY_H

#include <algorithm>
#include <cmath>
#include <limits>
#include <queue>
#include <utility>
#include <vector>

#include <Eigen/Core>

namespace geostation
{
  struct RoadGraph
  {
    std::vector<Eigen::Vector2d> nodes;
    std::vector<int> lineOf; //!< the polyline a node was sampled from (-1: a crossing)
    std::vector<std::vector<std::pair<int, double>>> edges;

    int add( const Eigen::Vector2d &p, int line )
    {
      nodes.push_back( p );
      lineOf.push_back( line );
      edges.emplace_back();
      return static_cast<int>( nodes.size() ) - 1;
    }
    void link( int a, int b )
    {
      const double d = ( nodes[a] - nodes[b] ).norm();
      edges[a].emplace_back( b, d );
      edges[b].emplace_back( a, d );
    }
    //! The nearest node within maxDistance, or -1.
    int nearest( const Eigen::Vector2d &p, double maxDistance ) const
    {
      int best = -1;
      double bestDistance = maxDistance;
      for ( size_t i = 0; i < nodes.size(); ++i )
        if ( const double d = ( nodes[i] - p ).norm(); d <= bestDistance )
        {
          bestDistance = d;
          best = static_cast<int>( i );
        }
      return best;
    }
    //! Dijkstra: path lengths from one node to every node (infinity where not connected).
    std::vector<double> pathLengthsFrom( int from ) const
    {
      std::vector<double> length( nodes.size(), std::numeric_limits<double>::infinity() );
      using Item = std::pair<double, int>;
      std::priority_queue<Item, std::vector<Item>, std::greater<Item>> open;
      length[from] = 0.0;
      open.push( { 0.0, from } );
      while ( !open.empty() )
      {
        const auto [d, n] = open.top();
        open.pop();
        if ( d > length[n] )
          continue;
        for ( const auto &[m, w] : edges[n] )
          if ( d + w < length[m] )
          {
            length[m] = d + w;
            open.push( { length[m], m } );
          }
      }
      return length;
    }
  };

  /**
   * Polylines (x, y in pixels; z ignored) as a graph: sampled at most
   * `spacingPx` apart, a node where two lines cross, and each open end
   * joined to the nearest node of another line within `endSnapPx`.
   */
  inline RoadGraph buildRoadGraph( const std::vector<std::vector<Eigen::Vector3d>> &lines, double endSnapPx, double spacingPx = 4.0 )
  {
    RoadGraph g;
    std::vector<std::pair<int, int>> segments;
    std::vector<int> ends;
    for ( size_t l = 0; l < lines.size(); ++l )
    {
      int previous = -1;
      for ( size_t i = 0; i < lines[l].size(); ++i )
      {
        const Eigen::Vector2d p = lines[l][i].head<2>();
        if ( previous >= 0 )
        {
          const Eigen::Vector2d a = g.nodes[previous];
          const int steps = std::max( 1, static_cast<int>( std::ceil( ( p - a ).norm() / spacingPx ) ) );
          for ( int k = 1; k <= steps; ++k )
          {
            const int n = g.add( a + ( p - a ) * ( static_cast<double>( k ) / steps ), static_cast<int>( l ) );
            g.link( previous, n );
            segments.emplace_back( previous, n );
            previous = n;
          }
        }
        else
        {
          previous = g.add( p, static_cast<int>( l ) );
          ends.push_back( previous );
        }
      }
      if ( previous >= 0 && ends.back() != previous )
        ends.push_back( previous );
    }
    // crossings of different lines
    const size_t n = segments.size();
    for ( size_t i = 0; i < n; ++i )
      for ( size_t k = i + 1; k < n; ++k )
      {
        const auto [a0, a1] = segments[i];
        const auto [b0, b1] = segments[k];
        if ( g.lineOf[a0] == g.lineOf[b0] )
          continue;
        const Eigen::Vector2d p = g.nodes[a0], r = g.nodes[a1] - p, q = g.nodes[b0], s = g.nodes[b1] - q;
        const double den = r.x() * s.y() - r.y() * s.x();
        if ( std::abs( den ) < 1e-12 )
          continue;
        const double t = ( ( q - p ).x() * s.y() - ( q - p ).y() * s.x() ) / den, u = ( ( q - p ).x() * r.y() - ( q - p ).y() * r.x() ) / den;
        if ( t < 0 || t > 1 || u < 0 || u > 1 )
          continue;
        const int x = g.add( p + t * r, -1 );
        for ( const int e : { a0, a1, b0, b1 } )
          g.link( x, e );
      }
    // open ends that stop short of another line
    for ( const int e : ends )
    {
      int best = -1;
      double bestDistance = endSnapPx;
      for ( size_t i = 0; i < g.nodes.size(); ++i )
        if ( g.lineOf[i] >= 0 && g.lineOf[i] != g.lineOf[e] )
          if ( const double d = ( g.nodes[i] - g.nodes[e] ).norm(); d <= bestDistance )
          {
            bestDistance = d;
            best = static_cast<int>( i );
          }
      if ( best >= 0 )
        g.link( e, best );
    }
    return g;
  }

  /**
   * One direction of APLS: control points every `controlSpacingPx` along
   * `from`, snapped to `to` within `snapPx`; pairs closer than the spacing
   * along `from`, or not connected in it, are not counted.
   */
  inline double pathLengthSimilarity( const RoadGraph &from, const RoadGraph &to, double controlSpacingPx, double snapPx, int *pairsCounted = nullptr )
  {
    std::vector<int> controls;
    for ( size_t i = 0; i < from.nodes.size(); ++i )
    {
      bool far = true;
      for ( const int c : controls )
        far = far && ( from.nodes[c] - from.nodes[i] ).norm() >= controlSpacingPx;
      if ( far )
        controls.push_back( static_cast<int>( i ) );
    }
    std::vector<int> snapped;
    for ( const int c : controls )
      snapped.push_back( to.nearest( from.nodes[c], snapPx ) );
    double penalty = 0.0;
    int pairs = 0;
    for ( size_t a = 0; a < controls.size(); ++a )
    {
      const std::vector<double> lengthFrom = from.pathLengthsFrom( controls[a] );
      const std::vector<double> lengthTo = snapped[a] >= 0 ? to.pathLengthsFrom( snapped[a] ) : std::vector<double>();
      for ( size_t b = a + 1; b < controls.size(); ++b )
      {
        const double l = lengthFrom[controls[b]];
        if ( !std::isfinite( l ) || l < controlSpacingPx )
          continue;
        ++pairs;
        if ( snapped[a] < 0 || snapped[b] < 0 || !std::isfinite( lengthTo[snapped[b]] ) )
        {
          penalty += 1.0;
          continue;
        }
        penalty += std::min( 1.0, std::abs( l - lengthTo[snapped[b]] ) / l );
      }
    }
    if ( pairsCounted )
      *pairsCounted = pairs;
    return pairs ? 1.0 - penalty / pairs : 0.0;
  }

  struct TopologyScore
  {
    double truthToResult = 0.0; //!< gaps, missing roads and broken junctions lower it
    double resultToTruth = 0.0; //!< false roads and false connections lower it
    double apls = 0.0;          //!< harmonic mean of the two
    int pairs = 0;
  };

  inline TopologyScore averagePathLengthSimilarity( const std::vector<std::vector<Eigen::Vector3d>> &truth, double truthEndSnapPx,
      const std::vector<std::vector<Eigen::Vector3d>> &result, double resultEndSnapPx, double controlSpacingPx, double snapPx )
  {
    const RoadGraph t = buildRoadGraph( truth, truthEndSnapPx ), r = buildRoadGraph( result, resultEndSnapPx );
    TopologyScore s;
    int pairsA = 0, pairsB = 0;
    s.truthToResult = pathLengthSimilarity( t, r, controlSpacingPx, snapPx, &pairsA );
    s.resultToTruth = pathLengthSimilarity( r, t, controlSpacingPx, snapPx, &pairsB );
    s.pairs = pairsA + pairsB;
    s.apls = s.truthToResult + s.resultToTruth > 0 ? 2.0 * s.truthToResult * s.resultToTruth / ( s.truthToResult + s.resultToTruth ) : 0.0;
    return s;
  }
}

#endif
