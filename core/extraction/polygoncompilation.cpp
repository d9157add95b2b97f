/***************************************************************************
  polygoncompilation.cpp - maximum-length polygons of a result matrix
 ***************************************************************************/
#include "extraction/polygoncompilation.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <optional>
#include <unordered_map>

#include <Eigen/LU>

#include "extraction/resultmatrix.h"
#include "imageproc/edgeprimitives.h"

namespace geostation
{

  namespace
  {
    Eigen::Vector2d centreOf( const Eigen::Vector2i &cell ) { return cell.cast<double>() + Eigen::Vector2d( 0.5, 0.5 ); }

    constexpr int kDc[8] = { 0, 1, 1, 1, 0, -1, -1, -1 };
    constexpr int kDr[8] = { -1, -1, 0, 1, 1, 1, 0, -1 };

    //! The chosen pixels within their bounding box, padded by one (their symbols); compilation works on this copy.
    struct Grid
    {
      cv::Mat on; // CV_8UC1, (box rows + 2) x (box cols + 2)
      int c0 = 0, r0 = 0;

      bool inside( int c, int r ) const { return c - c0 + 1 >= 0 && r - r0 + 1 >= 0 && c - c0 + 1 < on.cols && r - r0 + 1 < on.rows; }
      uint8_t symbol( int c, int r ) const { return inside( c, r ) ? on.at<uint8_t>( r - r0 + 1, c - c0 + 1 ) : 0; }
      bool at( int c, int r ) const { return symbol( c, r ) != 0; }
      void clear( int c, int r ) { on.at<uint8_t>( r - r0 + 1, c - c0 + 1 ) = 0; }
      long key( int c, int r ) const { return static_cast<long>( r - r0 + 1 ) * on.cols + ( c - c0 + 1 ); }
      int degree( int c, int r ) const
      {
        int n = 0;
        for ( int k = 0; k < 8; ++k )
          n += at( c + kDc[k], r + kDr[k] );
        return n;
      }
    };

    //! A traced string of pixels between two nodes (intersection ids, -1 for a dead end).
    struct RawPolygon
    {
      std::vector<Eigen::Vector2d> pixels;
      int startNode = -1, endNode = -1;
      bool live = true;
    };

    //! The compilation's steps on one set of symbols.
    class Compiler
    {
      public:
        //! Copies the chosen pixels out of the matrix; false when there are none.
        bool collect( const ResultMatrix &matrix, const std::string &symbols );
        //! Corner pixels (two neighbours that touch each other) carry nothing: a line's run then has exactly two neighbours.
        void removeCorners();
        //! Dead ends (one neighbour) and intersections (more than two), the latter's touching pixels grouped into one node.
        void findNodes();
        //! Every string from a node to the next, then the rings without a node.
        void trace();
        //! One-branch nodes become dead ends, two-branch nodes join their two lines.
        void resolveNodes();
        //! Each intersection where its branches' lines meet (least squares), not at the centroid of its pixels.
        void placeIntersections();
        CompilationSummary assemble( const std::string &symbols, int minPixels ) const;

        const std::vector<Eigen::Vector2i> &cells() const { return mCells; }

      private:
        int nodeOf( int c, int r ) const
        {
          const auto it = mNode.find( mGrid.key( c, r ) );
          return it == mNode.end() ? -1 : it->second;
        }
        void finish( std::vector<Eigen::Vector2d> pixels, int startNode, int endNode );
        std::vector<std::pair<size_t, bool>> branches( int node ) const;
        std::optional<Eigen::Vector2i> nextInRun( const Eigen::Vector2i &cur, const Eigen::Vector2i &prev, int startNode, size_t length ) const;

        Grid mGrid;
        cv::Mat mOriginal; // the symbols, for each polygon's record
        cv::Mat mVisited;
        std::vector<Eigen::Vector2i> mCells;
        std::unordered_map<long, int> mNode; // node id of a node pixel; run pixels have none
        std::vector<Eigen::Vector2d> mNodeCentre;
        std::vector<bool> mNodeIsIntersection;
        std::vector<RawPolygon> mRaw;
    };

    bool Compiler::collect( const ResultMatrix &matrix, const std::string &symbols )
    {
      bool chosen[256] = {};
      for ( const char c : symbols )
        chosen[static_cast<uint8_t>( c )] = true;
      int cMin = matrix.width(), cMax = -1, rMin = matrix.height(), rMax = -1;
      for ( int r = 0; r < matrix.height(); ++r )
      {
        const uint8_t *line = matrix.symbols().ptr<uint8_t>( r );
        for ( int c = 0; c < matrix.width(); ++c )
          if ( line[c] && chosen[line[c]] )
          {
            mCells.emplace_back( c, r );
            cMin = std::min( cMin, c );
            cMax = std::max( cMax, c );
            rMin = std::min( rMin, r );
            rMax = std::max( rMax, r );
          }
      }
      if ( mCells.empty() )
        return false;
      mGrid.c0 = cMin;
      mGrid.r0 = rMin;
      mGrid.on = cv::Mat::zeros( rMax - rMin + 3, cMax - cMin + 3, CV_8UC1 );
      for ( const Eigen::Vector2i &p : mCells )
        mGrid.on.at<uint8_t>( p.y() - rMin + 1, p.x() - cMin + 1 ) = matrix.symbols().at<uint8_t>( p.y(), p.x() );
      mOriginal = mGrid.on.clone();
      mVisited = cv::Mat::zeros( mGrid.on.rows, mGrid.on.cols, CV_8UC1 );
      return true;
    }

    void Compiler::removeCorners()
    {
      for ( int pass = 0; pass < 3; ++pass )
      {
        bool changed = false;
        for ( const Eigen::Vector2i &p : mCells )
        {
          if ( !mGrid.at( p.x(), p.y() ) || mGrid.degree( p.x(), p.y() ) != 2 )
            continue;
          Eigen::Vector2i nb[2];
          int k = 0;
          for ( int d = 0; d < 8; ++d )
            if ( mGrid.at( p.x() + kDc[d], p.y() + kDr[d] ) )
              nb[k++] = Eigen::Vector2i( p.x() + kDc[d], p.y() + kDr[d] );
          if ( ( nb[0] - nb[1] ).cwiseAbs().maxCoeff() == 1 )
          {
            mGrid.clear( p.x(), p.y() );
            changed = true;
          }
        }
        if ( !changed )
          break;
      }
    }

    void Compiler::findNodes()
    {
      for ( const Eigen::Vector2i &p : mCells )
      {
        if ( !mGrid.at( p.x(), p.y() ) || nodeOf( p.x(), p.y() ) >= 0 )
          continue;
        const int degree = mGrid.degree( p.x(), p.y() );
        if ( degree == 2 )
          continue;
        const int id = static_cast<int>( mNodeCentre.size() );
        mNode[mGrid.key( p.x(), p.y() )] = id;
        if ( degree < 3 )
        {
          mNodeCentre.push_back( centreOf( p ) );
          mNodeIsIntersection.push_back( false );
          continue;
        }
        // the crossing examination: all touching pixels of more than two neighbours form one intersection
        std::vector<Eigen::Vector2i> stack { p };
        Eigen::Vector2d sum = Eigen::Vector2d::Zero();
        int members = 0;
        while ( !stack.empty() )
        {
          const Eigen::Vector2i q = stack.back();
          stack.pop_back();
          sum += q.cast<double>();
          ++members;
          for ( int d = 0; d < 8; ++d )
          {
            const int c = q.x() + kDc[d], r = q.y() + kDr[d];
            if ( mGrid.at( c, r ) && nodeOf( c, r ) < 0 && mGrid.degree( c, r ) >= 3 )
            {
              mNode[mGrid.key( c, r )] = id;
              stack.emplace_back( c, r );
            }
          }
        }
        mNodeCentre.push_back( sum / members + Eigen::Vector2d( 0.5, 0.5 ) );
        mNodeIsIntersection.push_back( true );
      }
    }

    void Compiler::finish( std::vector<Eigen::Vector2d> pixels, int startNode, int endNode )
    {
      RawPolygon polygon;
      polygon.startNode = startNode >= 0 && mNodeIsIntersection[startNode] ? startNode : -1;
      polygon.endNode = endNode >= 0 && mNodeIsIntersection[endNode] ? endNode : -1;
      if ( polygon.startNode >= 0 && ( pixels.front() - mNodeCentre[startNode] ).norm() > 0.5 )
        pixels.insert( pixels.begin(), mNodeCentre[startNode] );
      if ( polygon.endNode >= 0 && ( pixels.back() - mNodeCentre[endNode] ).norm() > 0.5 )
        pixels.push_back( mNodeCentre[endNode] );
      if ( pixels.size() < 2 || ( startNode >= 0 && startNode == endNode && pixels.size() < 4 ) )
        return;
      polygon.pixels = std::move( pixels );
      mRaw.push_back( std::move( polygon ) );
    }

    std::optional<Eigen::Vector2i> Compiler::nextInRun( const Eigen::Vector2i &cur, const Eigen::Vector2i &prev, int startNode, size_t length ) const
    {
      for ( int e = 0; e < 8; ++e )
      {
        const Eigen::Vector2i q( cur.x() + kDc[e], cur.y() + kDr[e] );
        if ( q == prev || !mGrid.at( q.x(), q.y() ) )
          continue;
        const int node = nodeOf( q.x(), q.y() );
        if ( node >= 0 && !( node == startNode && length <= 2 ) )
          return q;
        if ( node < 0 && !mVisited.at<uint8_t>( q.y() - mGrid.r0 + 1, q.x() - mGrid.c0 + 1 ) )
          return q;
      }
      return std::nullopt;
    }

    void Compiler::trace()
    {
      const auto visited = [&]( int c, int r ) -> uint8_t & { return mVisited.at<uint8_t>( r - mGrid.r0 + 1, c - mGrid.c0 + 1 ); };
      std::map<std::pair<int, int>, int> directLinks;
      for ( const Eigen::Vector2i &p : mCells )
      {
        if ( !mGrid.at( p.x(), p.y() ) )
          continue;
        const int startNode = nodeOf( p.x(), p.y() );
        if ( startNode < 0 )
          continue;
        for ( int d = 0; d < 8; ++d )
        {
          const int c = p.x() + kDc[d], r = p.y() + kDr[d];
          if ( !mGrid.at( c, r ) )
            continue;
          const int nbNode = nodeOf( c, r );
          if ( nbNode >= 0 )
          {
            // two nodes side by side: one link between them
            const std::pair<int, int> key( std::min( startNode, nbNode ), std::max( startNode, nbNode ) );
            if ( nbNode != startNode && !directLinks.count( key ) )
            {
              directLinks[key] = 1;
              finish( { centreOf( p ), centreOf( Eigen::Vector2i( c, r ) ) }, startNode, nbNode );
            }
            continue;
          }
          if ( visited( c, r ) )
            continue;
          std::vector<Eigen::Vector2d> pixels { centreOf( p ), centreOf( Eigen::Vector2i( c, r ) ) };
          visited( c, r ) = 1;
          Eigen::Vector2i prev = p, cur( c, r );
          int endNode = -1;
          while ( const std::optional<Eigen::Vector2i> next = nextInRun( cur, prev, startNode, pixels.size() ) )
          {
            pixels.push_back( centreOf( *next ) );
            if ( ( endNode = nodeOf( next->x(), next->y() ) ) >= 0 )
              break;
            visited( next->x(), next->y() ) = 1;
            prev = cur;
            cur = *next;
          }
          finish( std::move( pixels ), startNode, endNode );
        }
      }
      // closed rings without a node
      for ( const Eigen::Vector2i &p : mCells )
      {
        if ( !mGrid.at( p.x(), p.y() ) || nodeOf( p.x(), p.y() ) >= 0 || visited( p.x(), p.y() ) )
          continue;
        std::vector<Eigen::Vector2d> pixels { centreOf( p ) };
        visited( p.x(), p.y() ) = 1;
        Eigen::Vector2i cur = p;
        while ( const std::optional<Eigen::Vector2i> next = nextInRun( cur, cur, -1, 0 ) )
        {
          visited( next->x(), next->y() ) = 1;
          pixels.push_back( centreOf( *next ) );
          cur = *next;
        }
        pixels.push_back( centreOf( p ) );
        finish( std::move( pixels ), -1, -1 );
      }
    }

    std::vector<std::pair<size_t, bool>> Compiler::branches( int node ) const
    {
      std::vector<std::pair<size_t, bool>> ends; // polygon, at its start
      for ( size_t i = 0; i < mRaw.size(); ++i )
        if ( mRaw[i].live )
        {
          if ( mRaw[i].startNode == node )
            ends.emplace_back( i, true );
          if ( mRaw[i].endNode == node )
            ends.emplace_back( i, false );
        }
      return ends;
    }

    void Compiler::resolveNodes()
    {
      for ( size_t node = 0; node < mNodeCentre.size(); ++node )
      {
        if ( !mNodeIsIntersection[node] )
          continue;
        const std::vector<std::pair<size_t, bool>> ends = branches( static_cast<int>( node ) );
        if ( ends.size() == 1 )
        {
          ( ends[0].second ? mRaw[ends[0].first].startNode : mRaw[ends[0].first].endNode ) = -1;
          mNodeIsIntersection[node] = false;
        }
        else if ( ends.size() == 2 && ends[0].first != ends[1].first )
        {
          RawPolygon &a = mRaw[ends[0].first], &b = mRaw[ends[1].first];
          if ( ends[0].second ) // a must end at the node
          {
            std::reverse( a.pixels.begin(), a.pixels.end() );
            std::swap( a.startNode, a.endNode );
          }
          if ( !ends[1].second ) // b must start there
          {
            std::reverse( b.pixels.begin(), b.pixels.end() );
            std::swap( b.startNode, b.endNode );
          }
          a.pixels.insert( a.pixels.end(), b.pixels.begin() + 1, b.pixels.end() );
          a.endNode = b.endNode;
          b.live = false;
          mNodeIsIntersection[node] = false;
        }
        else if ( ends.size() == 2 ) // a ring through one node
          mNodeIsIntersection[node] = false;
      }
    }

    //! The point `distance` px along a polyline from one of its ends.
    Eigen::Vector2d alongFromEnd( const std::vector<Eigen::Vector2d> &px, bool fromStart, double distance )
    {
      double travelled = 0.0;
      for ( size_t k = 1; k < px.size(); ++k )
      {
        const Eigen::Vector2d a = fromStart ? px[k - 1] : px[px.size() - k], b = fromStart ? px[k] : px[px.size() - 1 - k];
        const double step = ( b - a ).norm();
        if ( travelled + step >= distance && step > 0 )
          return a + ( b - a ) * ( ( distance - travelled ) / step );
        travelled += step;
      }
      return fromStart ? px.back() : px.front();
    }

    void Compiler::placeIntersections()
    {
      for ( size_t node = 0; node < mNodeCentre.size(); ++node )
      {
        if ( !mNodeIsIntersection[node] )
          continue;
        const std::vector<std::pair<size_t, bool>> ends = branches( static_cast<int>( node ) );
        Eigen::Matrix2d normal = Eigen::Matrix2d::Zero();
        Eigen::Vector2d rhs = Eigen::Vector2d::Zero();
        for ( const auto &[index, atStart] : ends )
        {
          const Eigen::Vector2d near = alongFromEnd( mRaw[index].pixels, atStart, 3.0 ), far = alongFromEnd( mRaw[index].pixels, atStart, 12.0 );
          if ( ( far - near ).norm() < 2.0 )
            continue;
          const Eigen::Vector2d d = ( far - near ).normalized();
          const Eigen::Matrix2d projector = Eigen::Matrix2d::Identity() - d * d.transpose();
          normal += projector;
          rhs += projector * near;
        }
        if ( std::abs( normal.determinant() ) < 0.05 )
          continue; // branches all but parallel: keep the centroid
        const Eigen::Vector2d meet = normal.inverse() * rhs;
        if ( ( meet - mNodeCentre[node] ).norm() > 8.0 )
          continue;
        for ( const auto &[index, atStart] : ends )
          ( atStart ? mRaw[index].pixels.front() : mRaw[index].pixels.back() ) = meet;
        mNodeCentre[node] = meet;
      }
    }

    CompilationSummary Compiler::assemble( const std::string &symbols, int minPixels ) const
    {
      CompilationSummary summary;
      for ( size_t i = 0; i < mNodeCentre.size(); ++i )
        if ( mNodeIsIntersection[i] && !branches( static_cast<int>( i ) ).empty() )
          summary.intersections.push_back( mNodeCentre[i] );
      for ( const RawPolygon &r : mRaw )
      {
        if ( !r.live )
          continue;
        CompiledPolygon polygon;
        polygon.startEnd = r.startNode >= 0 ? PolygonEnd::Intersection : PolygonEnd::DeadEnd;
        polygon.endEnd = r.endNode >= 0 ? PolygonEnd::Intersection : PolygonEnd::DeadEnd;
        const bool spur = polygon.startEnd == PolygonEnd::DeadEnd || polygon.endEnd == PolygonEnd::DeadEnd;
        if ( spur && static_cast<int>( r.pixels.size() ) < minPixels )
          continue;
        for ( const Eigen::Vector2d &p : r.pixels )
        {
          const int c = static_cast<int>( std::floor( p.x() ) ), row = static_cast<int>( std::floor( p.y() ) );
          const char v = mGrid.inside( c, row ) ? static_cast<char>( mOriginal.at<uint8_t>( row - mGrid.r0 + 1, c - mGrid.c0 + 1 ) ) : 0;
          if ( v && symbols.find( v ) != std::string::npos && polygon.symbols.find( v ) == std::string::npos )
            polygon.symbols.push_back( v );
        }
        polygon.pixels = douglasPeucker( r.pixels, 0.75 ); // the pixel staircase, straightened
        summary.polygons.push_back( std::move( polygon ) );
      }
      return summary;
    }
  } // namespace

  CompilationSummary compileMaxLengthPolygons( ResultMatrix &matrix, const std::string &symbols, bool erase, int minPixels )
  {
    Compiler compiler;
    if ( !compiler.collect( matrix, symbols ) )
      return CompilationSummary();
    if ( erase )
      for ( const Eigen::Vector2i &p : compiler.cells() )
        matrix.drawPolyline( { centreOf( p ) }, 0, true );
    compiler.removeCorners();
    compiler.findNodes();
    compiler.trace();
    compiler.resolveNodes();
    compiler.placeIntersections();
    return compiler.assemble( symbols, minPixels );
  }

} // namespace geostation
