/***************************************************************************
  lineprojection.cpp
 ***************************************************************************/
#include "geometry/lineprojection.h"

#include <algorithm>

namespace geostation
{

  ProjectedPolylineParts projectPolylineCut( const std::vector<Eigen::Vector3d> &dense, const GroundToPixel &project )
  {
    const auto boundary = [&]( const Eigen::Vector3d &inside, const Eigen::Vector3d &outside )
    {
      Eigen::Vector3d a = inside, b = outside;
      for ( int k = 0; k < 40; ++k )
      {
        const Eigen::Vector3d mid = 0.5 * ( a + b );
        ( project( mid ) ? a : b ) = mid;
      }
      return project( a );
    };
    std::vector<std::vector<Eigen::Vector2d>> runs( 1 );
    std::optional<Eigen::Vector2d> previous;
    for ( size_t i = 0; i < dense.size(); ++i )
    {
      const std::optional<Eigen::Vector2d> p = project( dense[i] );
      if ( p )
      {
        if ( runs.back().empty() && i > 0 )
          if ( const std::optional<Eigen::Vector2d> start = boundary( dense[i], dense[i - 1] ) )
            runs.back().push_back( *start );
        runs.back().push_back( *p );
      }
      else if ( !runs.back().empty() )
      {
        if ( const std::optional<Eigen::Vector2d> end = boundary( dense[i - 1], dense[i] ) )
          runs.back().push_back( *end );
        runs.emplace_back();
      }
    }
    ProjectedPolylineParts out;
    double bestLength = 0.0;
    for ( std::vector<Eigen::Vector2d> &run : runs )
    {
      if ( run.size() < 2 )
        continue;
      double length = 0.0;
      for ( size_t k = 1; k < run.size(); ++k )
        length += ( run[k] - run[k - 1] ).norm();
      if ( length > bestLength || out.longest < 0 )
      {
        bestLength = length;
        out.longest = static_cast<int>( out.parts.size() );
      }
      out.parts.push_back( std::move( run ) );
    }
    return out;
  }

  ProjectedGroundLine projectGroundLine( const OrientedImage &image, const std::vector<Eigen::Vector3d> &vertices, const GroundPointViewer &view,
                                         const GroundLineOptions &options )
  {
    ProjectedGroundLine out;
    // a vertex's pixel, its flags gathered into `into`
    const auto look = [&view]( const Eigen::Vector3d &ground, ProjectedGroundLine &into ) -> std::optional<Eigen::Vector2d>
    {
      const GroundPointView v = view( ground );
      into.allVisible = into.allVisible && v.visible;
      into.allInFrame = into.allInFrame && v.projection.inFrame;
      into.minDepthM = std::min( into.minDepthM, v.projection.depthM );
      if ( !v.projection.ok() )
      {
        into.behind = into.behind || v.projection.status == PixelProjection::Status::BehindCamera;
        return std::nullopt;
      }
      return v.projection.pixelInImage;
    };
    const auto densify = [&]( const std::vector<Eigen::Vector3d> &line ) { return densifyForImage( image, line, options.densifyPx, options.heightAt ); };

    const std::vector<Eigen::Vector3d> dense = densify( vertices );
    std::vector<Eigen::Vector2d> pixels;
    for ( const Eigen::Vector3d &g : dense )
      if ( const std::optional<Eigen::Vector2d> p = look( g, out ) )
        pixels.push_back( *p );
    if ( pixels.size() == dense.size() )
    {
      // all of it can be shown
      if ( options.closed && !pixels.empty() )
        pixels.back() = pixels.front();
      out.parts.push_back( std::move( pixels ) );
      return out;
    }
    if ( options.closed )
    {
      // a ring is clipped in 3-D to the part of space the image can show, then densified and projected
      std::vector<Eigen::Vector3d> ring( vertices.begin(), vertices.end() - ( vertices.size() > 1 && vertices.front() == vertices.back() ? 1 : 0 ) );
      ring = clipRingToImageField( image, ring );
      if ( ring.empty() )
        return out;
      ring.push_back( ring.front() );
      ProjectedGroundLine clippedRing;
      std::vector<Eigen::Vector2d> ringPixels;
      for ( const Eigen::Vector3d &g : densify( ring ) )
      {
        const std::optional<Eigen::Vector2d> p = look( g, clippedRing );
        if ( !p )
          return out;
        ringPixels.push_back( *p );
      }
      ringPixels.back() = ringPixels.front();
      out.allInFrame = out.allInFrame && clippedRing.allInFrame;
      out.allVisible = out.allVisible && clippedRing.allVisible;
      out.minDepthM = clippedRing.minDepthM; // of what is drawn
      out.clipped = true;
      out.parts.push_back( std::move( ringPixels ) );
      return out;
    }
    // a line is cut where it leaves the projectable space; the longest part first
    ProjectedGroundLine probe;
    ProjectedPolylineParts cut = projectPolylineCut( dense, [&]( const Eigen::Vector3d &g ) { return look( g, probe ); } );
    if ( cut.longest < 0 )
      return out;
    out.clipped = true;
    out.parts.push_back( std::move( cut.parts[cut.longest] ) );
    for ( int k = 0; k < static_cast<int>( cut.parts.size() ); ++k )
      if ( k != cut.longest )
        out.parts.push_back( std::move( cut.parts[k] ) );
    return out;
  }

  void FeatureProjectionTally::add( const GroundPointView &view )
  {
    allVisible &= view.visible;
    minDepthM = std::min( minDepthM, view.projection.depthM );
    allInFrame &= view.projection.inFrame;
    behind |= view.projection.status == PixelProjection::Status::BehindCamera;
  }

  void FeatureProjectionTally::add( const ProjectedGroundLine &line, bool partsDropped )
  {
    minDepthM = std::min( minDepthM, line.minDepthM );
    allInFrame &= line.allInFrame;
    allVisible &= line.allVisible;
    clipped |= line.clipped;
    behind |= line.behind || ( line.parts.size() > 1 && partsDropped );
  }

} // namespace geostation
