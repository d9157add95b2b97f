/***************************************************************************
  lineprojection.cpp
 ***************************************************************************/
#include "geometry/lineprojection.h"

#include <algorithm>

namespace geostation
{

  ProjectedPolylineParts projectPolylineCut( const std::vector<Eigen::Vector3d> &dense, const GroundToPixel &project, const GroundClass &classify )
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
    std::vector<int> runClasses( 1, 0 );
    for ( size_t i = 0; i < dense.size(); ++i )
    {
      const std::optional<Eigen::Vector2d> p = project( dense[i] );
      if ( p )
      {
        const int c = classify ? classify( dense[i] ) : 0;
        if ( !runs.back().empty() && c != runClasses.back() )
        {
          // the class changes: the last point ends this run and starts the next
          const Eigen::Vector2d shared = runs.back().back();
          runs.push_back( { shared } );
          runClasses.push_back( c );
        }
        if ( runs.back().empty() )
        {
          runClasses.back() = c;
          if ( i > 0 )
            if ( const std::optional<Eigen::Vector2d> start = boundary( dense[i], dense[i - 1] ) )
              runs.back().push_back( *start );
        }
        runs.back().push_back( *p );
      }
      else if ( !runs.back().empty() )
      {
        if ( const std::optional<Eigen::Vector2d> end = boundary( dense[i - 1], dense[i] ) )
          runs.back().push_back( *end );
        runs.emplace_back();
        runClasses.push_back( 0 );
      }
    }
    ProjectedPolylineParts out;
    double bestLength = 0.0;
    for ( size_t r = 0; r < runs.size(); ++r )
    {
      std::vector<Eigen::Vector2d> &run = runs[r];
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
      out.classes.push_back( runClasses[r] );
    }
    return out;
  }

  ProjectedGroundLine projectGroundLine( const OrientedImage &image, const std::vector<Eigen::Vector3d> &vertices, const GroundPointViewer &view,
                                         const GroundLineOptions &options )
  {
    ProjectedGroundLine out;
    // the viewer's answer for a ground point, the last one kept (the cut and the hidden test ask for the same point in turn)
    std::optional<std::pair<Eigen::Vector3d, GroundPointView>> last;
    const auto seen = [&view, &last]( const Eigen::Vector3d &ground ) -> const GroundPointView &
    {
      if ( !last || last->first != ground )
        last.emplace( ground, view( ground ) );
      return last->second;
    };
    // a vertex's pixel, its flags gathered into `into`
    const auto look = [&seen]( const Eigen::Vector3d &ground, ProjectedGroundLine &into ) -> std::optional<Eigen::Vector2d>
    {
      const GroundPointView &v = seen( ground );
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
    if ( pixels.size() == dense.size() && !( options.splitHidden && !out.allVisible ) )
    {
      // all of it can be shown (and none of it is hidden where that splits it)
      if ( options.closed && !options.splitHidden && !pixels.empty() )
        pixels.back() = pixels.front();
      out.parts.push_back( std::move( pixels ) );
      out.hidden.push_back( false );
      return out;
    }
    if ( options.closed && !options.splitHidden )
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
      out.hidden.push_back( false );
      return out;
    }
    // a line is cut where it leaves the projectable space (and, asked, where the terrain starts or stops hiding it); the longest part first
    ProjectedGroundLine probe;
    GroundClass hiddenClass;
    if ( options.splitHidden )
      hiddenClass = [&seen]( const Eigen::Vector3d &g ) { const GroundPointView &v = seen( g ); return v.projection.inFrame && !v.visible ? 1 : 0; };
    ProjectedPolylineParts cut = projectPolylineCut( dense, [&]( const Eigen::Vector3d &g ) { return look( g, probe ); }, hiddenClass );
    if ( cut.longest < 0 )
      return out;
    out.clipped = pixels.size() != dense.size();
    out.parts.push_back( std::move( cut.parts[cut.longest] ) );
    out.hidden.push_back( cut.classes[cut.longest] == 1 );
    for ( int k = 0; k < static_cast<int>( cut.parts.size() ); ++k )
      if ( k != cut.longest )
      {
        out.parts.push_back( std::move( cut.parts[k] ) );
        out.hidden.push_back( cut.classes[k] == 1 );
      }
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
