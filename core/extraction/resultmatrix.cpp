/***************************************************************************
  resultmatrix.cpp - the raster record of what was extracted
 ***************************************************************************/
#include "extraction/resultmatrix.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <unordered_map>
#include <stdexcept>

#include <Eigen/LU>
#include <opencv2/imgproc.hpp>

#include "imageproc/edgeprimitives.h"

namespace geostation
{

  ResultMatrix::ResultMatrix( int width, int height )
  {
    if ( width <= 0 || height <= 0 )
      throw std::invalid_argument( "a result matrix needs a positive size" );
    mSymbols = cv::Mat::zeros( height, width, CV_8UC1 );
  }

  uint8_t ResultMatrix::at( int col, int row ) const
  {
    if ( col < 0 || row < 0 || col >= mSymbols.cols || row >= mSymbols.rows )
      return 0;
    return mSymbols.at<uint8_t>( row, col );
  }

  void ResultMatrix::drawPolyline( const std::vector<Eigen::Vector2d> &pixelsInImage, uint8_t symbol, bool overwrite )
  {
    if ( pixelsInImage.empty() )
      return;
    const auto cell = []( const Eigen::Vector2d &p ) { return cv::Point( static_cast<int>( std::floor( p.x() ) ), static_cast<int>( std::floor( p.y() ) ) ); };
    const auto put = [&]( const cv::Point &c )
    {
      if ( c.x < 0 || c.y < 0 || c.x >= mSymbols.cols || c.y >= mSymbols.rows )
        return;
      uint8_t &v = mSymbols.at<uint8_t>( c.y, c.x );
      if ( overwrite || v == 0 )
        v = symbol;
    };
    put( cell( pixelsInImage.front() ) );
    for ( size_t i = 1; i < pixelsInImage.size(); ++i )
    {
      const cv::Point a = cell( pixelsInImage[i - 1] ), b = cell( pixelsInImage[i] );
      // Bresenham through the big canvas: LineIterator clips to the matrix
      cv::LineIterator it( mSymbols, a, b, 8 );
      for ( int k = 0; k < it.count; ++k, ++it )
        put( it.pos() );
    }
  }

  std::optional<Eigen::Vector2i> ResultMatrix::nearestSymbol( const Eigen::Vector2d &pixelInImage, double radiusPx, const std::string &symbols ) const
  {
    const int r = static_cast<int>( std::ceil( radiusPx ) );
    const int cc = static_cast<int>( std::floor( pixelInImage.x() ) ), rc = static_cast<int>( std::floor( pixelInImage.y() ) );
    std::optional<Eigen::Vector2i> best;
    double bestD2 = radiusPx * radiusPx;
    for ( int row = std::max( 0, rc - r ); row <= std::min( mSymbols.rows - 1, rc + r ); ++row )
    {
      const uint8_t *line = mSymbols.ptr<uint8_t>( row );
      for ( int col = std::max( 0, cc - r ); col <= std::min( mSymbols.cols - 1, cc + r ); ++col )
      {
        const uint8_t v = line[col];
        if ( v == 0 || ( !symbols.empty() && symbols.find( static_cast<char>( v ) ) == std::string::npos ) )
          continue;
        const double d2 = ( col + 0.5 - pixelInImage.x() ) * ( col + 0.5 - pixelInImage.x() ) + ( row + 0.5 - pixelInImage.y() ) * ( row + 0.5 - pixelInImage.y() );
        if ( d2 <= bestD2 )
        {
          bestD2 = d2;
          best = Eigen::Vector2i( col, row );
        }
      }
    }
    return best;
  }

  void ResultMatrix::erase( const std::string &symbols )
  {
    for ( int row = 0; row < mSymbols.rows; ++row )
    {
      uint8_t *line = mSymbols.ptr<uint8_t>( row );
      for ( int col = 0; col < mSymbols.cols; ++col )
        if ( line[col] && symbols.find( static_cast<char>( line[col] ) ) != std::string::npos )
          line[col] = 0;
    }
  }

  long ResultMatrix::count( const std::string &symbols ) const
  {
    long n = 0;
    for ( int row = 0; row < mSymbols.rows; ++row )
    {
      const uint8_t *line = mSymbols.ptr<uint8_t>( row );
      for ( int col = 0; col < mSymbols.cols; ++col )
        n += line[col] && symbols.find( static_cast<char>( line[col] ) ) != std::string::npos;
    }
    return n;
  }

  double polylineLength( const std::vector<Eigen::Vector2d> &polyline )
  {
    double length = 0.0;
    for ( size_t i = 1; i < polyline.size(); ++i )
      length += ( polyline[i] - polyline[i - 1] ).norm();
    return length;
  }

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
      int degree( int c, int r ) const
      {
        int n = 0;
        for ( int k = 0; k < 8; ++k )
          n += at( c + kDc[k], r + kDr[k] );
        return n;
      }
    };
  } // namespace

  CompilationSummary compileMaxLengthPolygons( ResultMatrix &matrix, const std::string &symbols, bool erase, int minPixels )
  {
    const int w = matrix.width(), h = matrix.height();
    bool chosen[256] = {};
    for ( const char c : symbols )
      chosen[static_cast<uint8_t>( c )] = true;
    std::vector<Eigen::Vector2i> cells;
    int cMin = w, cMax = -1, rMin = h, rMax = -1;
    for ( int r = 0; r < h; ++r )
    {
      const uint8_t *line = matrix.symbols().ptr<uint8_t>( r );
      for ( int c = 0; c < w; ++c )
        if ( line[c] && chosen[line[c]] )
        {
          cells.emplace_back( c, r );
          cMin = std::min( cMin, c );
          cMax = std::max( cMax, c );
          rMin = std::min( rMin, r );
          rMax = std::max( rMax, r );
        }
    }
    CompilationSummary empty;
    if ( cells.empty() )
      return empty;
    Grid grid;
    grid.c0 = cMin;
    grid.r0 = rMin;
    grid.on = cv::Mat::zeros( rMax - rMin + 3, cMax - cMin + 3, CV_8UC1 );
    for ( const Eigen::Vector2i &p : cells )
      grid.on.at<uint8_t>( p.y() - rMin + 1, p.x() - cMin + 1 ) = matrix.symbols().at<uint8_t>( p.y(), p.x() );
    const cv::Mat original = grid.on.clone(); // the symbols, for each polygon's record
    const auto originalSymbol = [&]( int c, int r ) -> uint8_t
    {
      return grid.inside( c, r ) ? original.at<uint8_t>( r - grid.r0 + 1, c - grid.c0 + 1 ) : 0;
    };
    if ( erase )
      for ( const Eigen::Vector2i &p : cells )
        matrix.drawPolyline( { centreOf( p ) }, 0, true );

    // Corner pixels (two neighbours that touch each other) carry nothing: remove them so a line's run has exactly two neighbours.
    for ( int pass = 0; pass < 3; ++pass )
    {
      bool changed = false;
      for ( const Eigen::Vector2i &p : cells )
      {
        if ( !grid.at( p.x(), p.y() ) || grid.degree( p.x(), p.y() ) != 2 )
          continue;
        Eigen::Vector2i nb[2];
        int k = 0;
        for ( int d = 0; d < 8; ++d )
          if ( grid.at( p.x() + kDc[d], p.y() + kDr[d] ) )
            nb[k++] = Eigen::Vector2i( p.x() + kDc[d], p.y() + kDr[d] );
        if ( ( nb[0] - nb[1] ).cwiseAbs().maxCoeff() == 1 )
        {
          grid.clear( p.x(), p.y() );
          changed = true;
        }
      }
      if ( !changed )
        break;
    }

    // Nodes: dead ends (one neighbour) and intersections (more than two), the latter grouped into one node each.
    std::unordered_map<long, int> node; // node id of a node pixel; run pixels have none
    std::vector<Eigen::Vector2d> nodeCentre;
    std::vector<bool> nodeIsIntersection;
    const auto key = [&]( int c, int r ) { return static_cast<long>( r - grid.r0 + 1 ) * grid.on.cols + ( c - grid.c0 + 1 ); };
    const auto nodeOf = [&]( int c, int r ) -> int
    {
      const auto it = node.find( key( c, r ) );
      return it == node.end() ? -1 : it->second;
    };
    const auto setNode = [&]( int c, int r, int id ) { node[key( c, r )] = id; };
    for ( const Eigen::Vector2i &p : cells )
    {
      if ( !grid.at( p.x(), p.y() ) || nodeOf( p.x(), p.y() ) >= 0 )
        continue;
      const int degree = grid.degree( p.x(), p.y() );
      if ( degree == 2 )
        continue;
      const int id = static_cast<int>( nodeCentre.size() );
      if ( degree < 3 )
      {
        setNode( p.x(), p.y(), id );
        nodeCentre.push_back( centreOf( p ) );
        nodeIsIntersection.push_back( false );
        continue;
      }
      // the crossing examination: all touching pixels of more than two neighbours form one intersection
      std::vector<Eigen::Vector2i> stack { p };
      setNode( p.x(), p.y(), id );
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
          if ( grid.at( c, r ) && nodeOf( c, r ) < 0 && grid.degree( c, r ) >= 3 )
          {
            setNode( c, r, id );
            stack.emplace_back( c, r );
          }
        }
      }
      nodeCentre.push_back( sum / members + Eigen::Vector2d( 0.5, 0.5 ) );
      nodeIsIntersection.push_back( true );
    }

    struct RawPolygon
    {
      std::vector<Eigen::Vector2d> pixels;
      int startNode = -1, endNode = -1; //!< intersection nodes only
      bool live = true;
    };
    std::vector<RawPolygon> raw;
    cv::Mat visited = cv::Mat::zeros( grid.on.rows, grid.on.cols, CV_8UC1 );
    const auto visitedAt = [&]( int c, int r ) -> uint8_t & { return visited.at<uint8_t>( r - grid.r0 + 1, c - grid.c0 + 1 ); };
    std::map<std::pair<int, int>, int> directLinks;
    const auto finish = [&]( std::vector<Eigen::Vector2d> pixels, int startNode, int endNode )
    {
      RawPolygon polygon;
      polygon.startNode = startNode >= 0 && nodeIsIntersection[startNode] ? startNode : -1;
      polygon.endNode = endNode >= 0 && nodeIsIntersection[endNode] ? endNode : -1;
      if ( polygon.startNode >= 0 && ( pixels.front() - nodeCentre[startNode] ).norm() > 0.5 )
        pixels.insert( pixels.begin(), nodeCentre[startNode] );
      if ( polygon.endNode >= 0 && ( pixels.back() - nodeCentre[endNode] ).norm() > 0.5 )
        pixels.push_back( nodeCentre[endNode] );
      if ( pixels.size() < 2 || ( startNode >= 0 && startNode == endNode && pixels.size() < 4 ) )
        return;
      polygon.pixels = std::move( pixels );
      raw.push_back( std::move( polygon ) );
    };

    for ( const Eigen::Vector2i &p : cells )
    {
      if ( !grid.at( p.x(), p.y() ) )
        continue;
      const int startNode = nodeOf( p.x(), p.y() );
      if ( startNode < 0 )
        continue;
      for ( int d = 0; d < 8; ++d )
      {
        const int c = p.x() + kDc[d], r = p.y() + kDr[d];
        if ( !grid.at( c, r ) )
          continue;
        const int nbNode = nodeOf( c, r );
        if ( nbNode >= 0 )
        {
          if ( nbNode == startNode )
            continue;
          const std::pair<int, int> key( std::min( startNode, nbNode ), std::max( startNode, nbNode ) );
          if ( directLinks.count( key ) )
            continue;
          directLinks[key] = 1;
          finish( { centreOf( p ), centreOf( Eigen::Vector2i( c, r ) ) }, startNode, nbNode );
          continue;
        }
        if ( visitedAt( c, r ) )
          continue;
        std::vector<Eigen::Vector2d> pixels { centreOf( p ), centreOf( Eigen::Vector2i( c, r ) ) };
        visitedAt( c, r ) = 1;
        Eigen::Vector2i prev = p, cur( c, r );
        int endNode = -1;
        while ( true )
        {
          std::optional<Eigen::Vector2i> next;
          for ( int e = 0; e < 8 && !next; ++e )
          {
            const Eigen::Vector2i q( cur.x() + kDc[e], cur.y() + kDr[e] );
            if ( q == prev || !grid.at( q.x(), q.y() ) )
              continue;
            if ( nodeOf( q.x(), q.y() ) >= 0 && !( nodeOf( q.x(), q.y() ) == startNode && pixels.size() <= 2 ) )
              next = q;
            else if ( nodeOf( q.x(), q.y() ) < 0 && !visitedAt( q.x(), q.y() ) )
              next = q;
          }
          if ( !next )
            break;
          pixels.push_back( centreOf( *next ) );
          if ( nodeOf( next->x(), next->y() ) >= 0 )
          {
            endNode = nodeOf( next->x(), next->y() );
            break;
          }
          visitedAt( next->x(), next->y() ) = 1;
          prev = cur;
          cur = *next;
        }
        finish( std::move( pixels ), startNode, endNode );
      }
    }

    // closed rings without a node
    for ( const Eigen::Vector2i &p : cells )
    {
      if ( !grid.at( p.x(), p.y() ) || nodeOf( p.x(), p.y() ) >= 0 || visitedAt( p.x(), p.y() ) )
        continue;
      std::vector<Eigen::Vector2d> pixels { centreOf( p ) };
      visitedAt( p.x(), p.y() ) = 1;
      Eigen::Vector2i cur = p;
      while ( true )
      {
        std::optional<Eigen::Vector2i> next;
        for ( int e = 0; e < 8 && !next; ++e )
        {
          const Eigen::Vector2i q( cur.x() + kDc[e], cur.y() + kDr[e] );
          if ( grid.at( q.x(), q.y() ) && !visitedAt( q.x(), q.y() ) )
            next = q;
        }
        if ( !next )
          break;
        visitedAt( next->x(), next->y() ) = 1;
        pixels.push_back( centreOf( *next ) );
        cur = *next;
      }
      pixels.push_back( centreOf( p ) );
      finish( std::move( pixels ), -1, -1 );
    }

    // A node that only one line leaves is the blob at a line's end (a dead end); a node two lines leave is a bend
    // of one line (the two are joined); only three or more make an intersection.
    const auto branches = [&]( int node )
    {
      std::vector<std::pair<size_t, bool>> ends; // polygon, at its start
      for ( size_t i = 0; i < raw.size(); ++i )
        if ( raw[i].live )
        {
          if ( raw[i].startNode == node )
            ends.emplace_back( i, true );
          if ( raw[i].endNode == node )
            ends.emplace_back( i, false );
        }
      return ends;
    };
    for ( size_t node = 0; node < nodeCentre.size(); ++node )
    {
      if ( !nodeIsIntersection[node] )
        continue;
      std::vector<std::pair<size_t, bool>> ends = branches( static_cast<int>( node ) );
      if ( ends.size() == 1 )
      {
        ( ends[0].second ? raw[ends[0].first].startNode : raw[ends[0].first].endNode ) = -1;
        nodeIsIntersection[node] = false;
      }
      else if ( ends.size() == 2 && ends[0].first != ends[1].first )
      {
        RawPolygon &a = raw[ends[0].first], &b = raw[ends[1].first];
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
        nodeIsIntersection[node] = false;
      }
      else if ( ends.size() == 2 ) // a ring through one node
        nodeIsIntersection[node] = false;
    }

    // the crossing examined: the intersection lies where its branches' lines meet (least squares), not at the centroid of its pixels
    for ( size_t node = 0; node < nodeCentre.size(); ++node )
    {
      if ( !nodeIsIntersection[node] )
        continue;
      const std::vector<std::pair<size_t, bool>> ends = branches( static_cast<int>( node ) );
      Eigen::Matrix2d normal = Eigen::Matrix2d::Zero();
      Eigen::Vector2d rhs = Eigen::Vector2d::Zero();
      for ( const auto &[index, atStart] : ends )
      {
        const std::vector<Eigen::Vector2d> &px = raw[index].pixels;
        const auto along = [&]( double distance ) -> Eigen::Vector2d
        {
          // the point `distance` px along the branch from the node
          double travelled = 0.0;
          for ( size_t k = 1; k < px.size(); ++k )
          {
            const Eigen::Vector2d a = atStart ? px[k - 1] : px[px.size() - k], b = atStart ? px[k] : px[px.size() - 1 - k];
            const double step = ( b - a ).norm();
            if ( travelled + step >= distance && step > 0 )
              return a + ( b - a ) * ( ( distance - travelled ) / step );
            travelled += step;
          }
          return atStart ? px.back() : px.front();
        };
        const Eigen::Vector2d near = along( 3.0 ), far = along( 12.0 );
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
      if ( ( meet - nodeCentre[node] ).norm() > 8.0 )
        continue;
      for ( const auto &[index, atStart] : ends )
        ( atStart ? raw[index].pixels.front() : raw[index].pixels.back() ) = meet;
      nodeCentre[node] = meet;
    }

    CompilationSummary summary;
    for ( size_t i = 0; i < nodeCentre.size(); ++i )
      if ( nodeIsIntersection[i] && !branches( static_cast<int>( i ) ).empty() )
        summary.intersections.push_back( nodeCentre[i] );
    for ( RawPolygon &r : raw )
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
        const char v = static_cast<char>( originalSymbol( static_cast<int>( std::floor( p.x() ) ), static_cast<int>( std::floor( p.y() ) ) ) );
        if ( v && symbols.find( v ) != std::string::npos && polygon.symbols.find( v ) == std::string::npos )
          polygon.symbols.push_back( v );
      }
      polygon.pixels = douglasPeucker( r.pixels, 0.75 ); // the pixel staircase, straightened
      summary.polygons.push_back( std::move( polygon ) );
    }
    return summary;
  }

} // namespace geostation
