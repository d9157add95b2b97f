/***************************************************************************
  directionalfollower.cpp - directional-matrix line following (§6.3.1)
 ***************************************************************************/
#include "tracing/directionalfollower.h"
#include "geometry/rotation.h"

#include <algorithm>
#include <cmath>
#include <unordered_set>

#include <opencv2/imgproc.hpp>

#include "imageproc/edgeprimitives.h"
#include "tracing/lineprofile.h"

namespace geostation
{
  namespace
  {
    double deviationDeg( const Eigen::Vector2d &offset, const Eigen::Vector2d &direction )
    {
      return std::acos( std::clamp( offset.normalized().dot( direction ), -1.0, 1.0 ) ) * 180.0 / kPi;
    }

    DirectionalMatrix makeMatrix( double degrees, double minRadius, double maxRadius, double maxDeviation, bool fartherFirst )
    {
      DirectionalMatrix m;
      m.directionDeg = degrees;
      const Eigen::Vector2d d = directionFromDegrees( degrees );
      struct Entry
      {
        Eigen::Vector2i offset;
        double key1, key2;
      };
      std::vector<Entry> entries;
      const int r = static_cast<int>( std::ceil( maxRadius ) );
      for ( int dy = -r; dy <= r; ++dy )
        for ( int dx = -r; dx <= r; ++dx )
        {
          const Eigen::Vector2d o( dx, dy );
          const double length = fartherFirst ? std::max( std::abs( dx ), std::abs( dy ) ) : o.norm();
          if ( ( dx == 0 && dy == 0 ) || length < minRadius || length > maxRadius )
            continue;
          const double dev = deviationDeg( o, d );
          if ( dev > maxDeviation + 1e-9 )
            continue;
          if ( fartherFirst )
            entries.push_back( { Eigen::Vector2i( dx, dy ), -std::round( o.dot( d ) ), dev } );
          else
            entries.push_back( { Eigen::Vector2i( dx, dy ), o.norm() + 0.1 * dev, dev } );
        }
      std::stable_sort( entries.begin(), entries.end(), []( const Entry &a, const Entry &b ) { return a.key1 != b.key1 ? a.key1 < b.key1 : a.key2 < b.key2; } );
      for ( const Entry &e : entries )
        m.offsets.push_back( e.offset );
      return m;
    }

    int matrixIndex( const Eigen::Vector2d &direction, double stepDeg )
    {
      double deg = degreesFromDirection( direction );
      if ( deg < 0 )
        deg += 360.0;
      const int n = static_cast<int>( std::lround( 360.0 / stepDeg ) );
      return static_cast<int>( std::lround( deg / stepDeg ) ) % n;
    }

    struct AreaOfInterest
    {
      cv::Rect rect;
      cv::Mat skeleton;
      bool contains( const Eigen::Vector2i &p, int margin ) const
      {
        return p.x() >= rect.x + margin && p.y() >= rect.y + margin && p.x() < rect.x + rect.width - margin && p.y() < rect.y + rect.height - margin;
      }
      bool on( const Eigen::Vector2i &p ) const { return contains( p, 0 ) && skeleton.at<uint8_t>( p.y() - rect.y, p.x() - rect.x ) != 0; }
    };
  }

  const std::vector<DirectionalMatrix> &directionalMatrices()
  {
    static const std::vector<DirectionalMatrix> matrices = []
    {
      std::vector<DirectionalMatrix> m;
      for ( int k = 0; k < 24; ++k )
        m.push_back( makeMatrix( 15.0 * k, 1.0, 2.0, 60.0, true ) );
      return m;
    }();
    return matrices;
  }

  const std::vector<DirectionalMatrix> &largeDirectionalMatrices()
  {
    static const std::vector<DirectionalMatrix> matrices = []
    {
      std::vector<DirectionalMatrix> m;
      for ( int k = 0; k < 8; ++k )
        for ( int size = 0; size < 3; ++size )
          m.push_back( makeMatrix( 45.0 * k, 3.0, 5.0 + 2.0 * size, 35.0, false ) );
      return m;
    }();
    return matrices;
  }

  cv::Mat lineSkeleton( const cv::Mat &grey, const cv::Rect &area, const LineProfile &profile, const Eigen::Vector2d &direction, const FollowOptions &options )
  {
    const cv::Mat roi = grey( area );
    cv::Mat response;
    double threshold = std::max( options.minContrastGrey, options.minContrastFraction * profile.contrast );
    if ( profile.kind == LineKind::Edge )
    {
      cv::Mat gx, gy;
      cv::Sobel( roi, gx, CV_32F, 1, 0, 3, 1.0 / 8.0 );
      cv::Sobel( roi, gy, CV_32F, 0, 1, 3, 1.0 / 8.0 );
      const Eigen::Vector2d n = rightNormal( direction ) * profile.polarity;
      response = static_cast<float>( n.x() ) * gx + static_cast<float>( n.y() ) * gy;
      threshold *= 0.5; // the steepest slope of a step is about half its height per pixel
    }
    else
    {
      const int k = std::min( 61, 2 * static_cast<int>( std::ceil( profile.widthPx ) ) + 3 ) | 1;
      const cv::Mat kernel = cv::getStructuringElement( cv::MORPH_ELLIPSE, cv::Size( k, k ) );
      cv::morphologyEx( roi, response, profile.kind == LineKind::BrightStripe ? cv::MORPH_TOPHAT : cv::MORPH_BLACKHAT, kernel );
      response.convertTo( response, CV_32F );
    }
    cv::Mat binary = binarise( response, threshold );
    skeletonise( binary );
    return binary;
  }

  FollowResult followDirectional( const cv::Mat &grey, const FollowRequest &request, const DirectionalOptions &options )
  {
    FollowResult out;
    out.profile = request.profile;
    Eigen::Vector2d direction = request.direction.normalized();
    const cv::Rect image( 0, 0, grey.cols, grey.rows );
    AreaOfInterest area;
    const auto makeArea = [&]( const Eigen::Vector2d &centre )
    {
      const int half = options.areaPx / 2;
      area.rect = cv::Rect( static_cast<int>( centre.x() ) - half, static_cast<int>( centre.y() ) - half, options.areaPx, options.areaPx ) & image;
      area.skeleton = area.rect.area() > 0 ? lineSkeleton( grey, area.rect, out.profile, direction, options.follow ) : cv::Mat();
    };
    makeArea( request.start + 0.25 * options.areaPx * direction );

    // start on the skeleton pixel nearest the start
    Eigen::Vector2i current( -1, -1 );
    double bestDistance = 3.5;
    for ( int dy = -3; dy <= 3; ++dy )
      for ( int dx = -3; dx <= 3; ++dx )
      {
        const Eigen::Vector2i p( static_cast<int>( request.start.x() ) + dx, static_cast<int>( request.start.y() ) + dy );
        const double dist = ( p.cast<double>() + Eigen::Vector2d( 0.5, 0.5 ) - request.start ).norm();
        if ( area.on( p ) && dist < bestDistance )
        {
          bestDistance = dist;
          current = p;
        }
      }
    if ( current.x() < 0 )
    {
      out.stop = TraceStop::NoEdge;
      return out;
    }
    const auto centreOf = []( const Eigen::Vector2i &p ) { return Eigen::Vector2d( p.x() + 0.5, p.y() + 0.5 ); };
    std::unordered_set<long> visited;
    const auto key = [&]( const Eigen::Vector2i &p ) { return static_cast<long>( p.y() ) * grey.cols + p.x(); };
    const auto markAround = [&]( const Eigen::Vector2i &p )
    {
      for ( int dy = -1; dy <= 1; ++dy )
        for ( int dx = -1; dx <= 1; ++dx )
          visited.insert( key( p + Eigen::Vector2i( dx, dy ) ) );
    };
    markAround( current );
    std::vector<Eigen::Vector2d> vertices { centreOf( current ) };
    Eigen::Vector2i countPoint = current;
    const std::vector<DirectionalMatrix> &small = directionalMatrices();
    const std::vector<DirectionalMatrix> &large = largeDirectionalMatrices();
    const auto search = [&]( const DirectionalMatrix &m, Eigen::Vector2i &found )
    {
      for ( const Eigen::Vector2i &o : m.offsets )
      {
        const Eigen::Vector2i q = current + o;
        if ( area.on( q ) && !visited.count( key( q ) ) )
        {
          found = q;
          return true;
        }
      }
      return false;
    };

    out.stop = TraceStop::EndOfLine;
    for ( int step = 0; step < request.maxSteps; ++step )
    {
      if ( !area.contains( current, 10 ) )
        makeArea( centreOf( current ) + 0.3 * options.areaPx * direction );
      const int index = matrixIndex( direction, 15.0 );
      Eigen::Vector2i next;
      bool found = search( small[index], next );
      for ( int k = 1; !found && k <= options.adjacentMatrices; ++k )
        found = search( small[( index + k ) % 24], next ) || search( small[( index + 24 - k ) % 24], next );
      for ( int size = 0; !found && size < 3; ++size )
        found = search( large[3 * matrixIndex( direction, 45.0 ) + size], next );
      if ( !found )
        break;
      const Eigen::Vector2d nextCentre = centreOf( next );
      if ( request.withinLimit && !request.withinLimit( nextCentre ) )
      {
        out.stop = TraceStop::DistanceLimit;
        break;
      }
      // the pixels stepped over count as visited too, so the path never turns back on itself
      const Eigen::Vector2i delta = next - current;
      const int n = std::max( std::abs( delta.x() ), std::abs( delta.y() ) );
      for ( int k = 1; k <= n; ++k )
        markAround( current + ( delta.cast<double>() * k / n ).array().round().cast<int>().matrix() );
      out.pixelsFollowed += n;
      current = next;
      const Eigen::Vector2d moved = ( current - countPoint ).cast<double>();
      if ( moved.norm() >= options.follow.directionUpdatePx )
      {
        const Eigen::Vector2d updated = moved.normalized();
        if ( deviationDeg( updated, direction ) > options.follow.maxDirectionChangeDeg )
        {
          out.stop = TraceStop::DirectionChange;
          break;
        }
        direction = updated;
        vertices.push_back( centreOf( current ) );
        countPoint = current;
      }
    }
    if ( ( centreOf( current ) - vertices.back() ).norm() > 2.0 )
      vertices.push_back( centreOf( current ) );

    // each vertex refined across the line; the stripe width follows the line as it narrows
    LocateOptions locate = locateOptionsFor( out.profile, options.follow, 3.0 );
    for ( size_t i = 0; i < vertices.size(); ++i )
    {
      const Eigen::Vector2d local = vertices.size() > 1 ? ( vertices[std::min( i + 1, vertices.size() - 1 )] - vertices[i == 0 ? 0 : i - 1] ).normalized() : direction;
      if ( const std::optional<LineHit> hit = locateLine( grey, vertices[i], local, out.profile, locate ) )
      {
        out.points.push_back( hit->pixelInImage );
        out.sigmaPx.push_back( hit->sigmaPx );
        if ( out.profile.kind != LineKind::Edge )
          out.profile.widthPx = 0.7 * out.profile.widthPx + 0.3 * hit->widthPx;
      }
      else
      {
        out.points.push_back( vertices[i] );
        out.sigmaPx.push_back( 0.5 );
      }
    }
    out.direction = direction;
    return out;
  }

} // namespace geostation
