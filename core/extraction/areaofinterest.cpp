/***************************************************************************
  areaofinterest.cpp - sample lines across a rectangle
 ***************************************************************************/
#include "extraction/areaofinterest.h"
#include "geometry/rotation.h"

#include <algorithm>
#include <cmath>

#include "extraction/crossprofile.h"

namespace geostation
{

  Eigen::Vector2d AreaOfInterest::pointOn( int line, double offsetPx ) const
  {
    return origin + ( line + 1 ) * spacingPx * axis + offsetPx * normalOf( axis );
  }

  namespace
  {
    //! The best support for (line, offset) from the candidates of another line `gap` lines away.
    double support( const std::vector<AreaCandidate> &other, double offsetPx, int gap, double slopePerLine )
    {
      double best = 0.0;
      for ( const AreaCandidate &c : other )
        if ( std::abs( c.offsetPx - offsetPx ) <= slopePerLine * gap + 1.5 )
          best = std::max( best, std::min( 1.0, c.confidence / 0.5 ) ); // a neighbour of half the expected contrast supports fully
      return best;
    }
  } // namespace

  std::vector<std::vector<AreaCandidate>> analyseArea( const cv::Mat &grey, const AreaOfInterest &area, const AreaAnalysisOptions &options,
                                                       const std::optional<double> &startOffsetPx )
  {
    const int lines = area.lineCount();
    const int half = static_cast<int>( std::ceil( area.halfWidthPx + options.widthPx ) ) + 3;
    std::vector<std::vector<AreaCandidate>> candidates( lines );
    const double contrast = std::max( 1.0, options.contrast );
    for ( int j = 0; j < lines; ++j )
    {
      const Eigen::Vector2d centre = area.pointOn( j, 0.0 );
      const std::vector<double> profile = sampleCrossProfile( grey, centre, area.axis, half, options.polarity, 0.5 * area.spacingPx, 3 );
      const std::vector<double> response = bandResponse( profile, options.widthPx, options.polarity );
      std::vector<AreaCandidate> line;
      for ( int i = 1; i + 1 < static_cast<int>( response.size() ); ++i )
      {
        const double r = response[i];
        if ( std::isnan( r ) || std::abs( i - half ) > area.halfWidthPx )
          continue;
        // local maxima only (plateaus: the first sample)
        if ( !( r > response[i - 1] || std::isnan( response[i - 1] ) ) || !( r >= response[i + 1] || std::isnan( response[i + 1] ) ) )
          continue;
        const double confidence = std::min( 1.5, r / contrast );
        if ( confidence < options.semiThreshold )
          continue;
        // sub-pixel peak by a parabola
        double offset = i - half;
        const double a = response[i - 1], c = response[i + 1];
        if ( !std::isnan( a ) && !std::isnan( c ) && a - 2 * r + c < 0 )
          offset += std::clamp( 0.5 * ( a - c ) / ( a - 2 * r + c ), -0.5, 0.5 );
        line.push_back( { offset, confidence } );
      }
      std::sort( line.begin(), line.end(), []( const AreaCandidate &x, const AreaCandidate &y ) { return x.confidence > y.confidence; } );
      if ( static_cast<int>( line.size() ) > options.candidatesPerLine )
        line.resize( options.candidatesPerLine );
      candidates[j] = std::move( line );
    }

    // collinearity relaxation
    const double slope = std::tan( options.maxAngleDeg * kPi / 180.0 ) * area.spacingPx;
    for ( int iteration = 0; iteration < options.relaxationIterations; ++iteration )
    {
      std::vector<std::vector<AreaCandidate>> next = candidates;
      for ( int j = 0; j < lines; ++j )
        for ( size_t i = 0; i < candidates[j].size(); ++i )
        {
          const double t = candidates[j][i].offsetPx;
          double before = 0.0, after = 0.0;
          if ( j == 0 && startOffsetPx )
            before = std::abs( *startOffsetPx - t ) <= slope + 1.5 ? 1.0 : 0.0;
          for ( int g = 1; g <= 3; ++g )
          {
            const double weight = 1.2 - 0.2 * g;
            if ( j - g >= 0 )
              before = std::max( before, weight * support( candidates[j - g], t, g, slope ) );
            if ( j + g < lines )
              after = std::max( after, weight * support( candidates[j + g], t, g, slope ) );
          }
          if ( j == lines - 1 )
            after = before; // the area ends here, not the line
          if ( j == 0 && !startOffsetPx )
            before = after;
          next[j][i].confidence = std::min( 1.5, candidates[j][i].confidence * ( 0.6 + 0.25 * ( before + after ) ) );
        }
      candidates = std::move( next );
    }
    for ( std::vector<AreaCandidate> &line : candidates )
      line.erase( std::remove_if( line.begin(), line.end(), [&]( const AreaCandidate &c ) { return c.confidence < options.confirmThreshold; } ), line.end() );
    return candidates;
  }

  std::vector<ChainLink> bestChain( const std::vector<std::vector<AreaCandidate>> &lines, const AreaOfInterest &area, const AreaAnalysisOptions &options,
                                    const std::optional<double> &startOffsetPx )
  {
    struct Node
    {
      int line;
      double offset, confidence, score;
      int previous;
    };
    const double slope = std::tan( options.maxAngleDeg * kPi / 180.0 ) * area.spacingPx;
    constexpr double kGapCost = 0.3;
    std::vector<Node> nodes;
    std::vector<std::vector<int>> nodesOfLine( lines.size() );
    for ( size_t j = 0; j < lines.size(); ++j )
      for ( const AreaCandidate &c : lines[j] )
      {
        Node node { static_cast<int>( j ), c.offsetPx, c.confidence, -1e9, -1 };
        // a start: the line's last point (REM), or anywhere (verification)
        if ( startOffsetPx )
        {
          const int gap = static_cast<int>( j );
          if ( gap <= options.maxGapLines && std::abs( c.offsetPx - *startOffsetPx ) <= slope * ( gap + 1 ) + 1.5 )
            node.score = c.confidence - kGapCost * gap;
        }
        else
          node.score = c.confidence;
        for ( int g = 1; g <= options.maxGapLines + 1; ++g )
        {
          if ( static_cast<int>( j ) - g < 0 )
            break;
          for ( int k : nodesOfLine[j - g] )
          {
            const Node &p = nodes[k];
            if ( p.score < -1e8 || std::abs( c.offsetPx - p.offset ) > slope * g + 1.5 )
              continue;
            const double s = p.score + c.confidence - kGapCost * ( g - 1 ) - 0.02 * std::abs( c.offsetPx - p.offset );
            if ( s > node.score )
            {
              node.score = s;
              node.previous = k;
            }
          }
        }
        nodesOfLine[j].push_back( static_cast<int>( nodes.size() ) );
        nodes.push_back( node );
      }
    int best = -1;
    for ( size_t k = 0; k < nodes.size(); ++k )
      if ( nodes[k].score > -1e8 && ( best < 0 || nodes[k].score > nodes[best].score ) )
        best = static_cast<int>( k );
    std::vector<ChainLink> chain;
    for ( int k = best; k >= 0; k = nodes[k].previous )
      chain.push_back( { nodes[k].line, nodes[k].offset, nodes[k].confidence } );
    std::reverse( chain.begin(), chain.end() );
    return chain;
  }

} // namespace geostation
