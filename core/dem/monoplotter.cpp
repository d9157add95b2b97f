/***************************************************************************
  monoplotter.cpp - one oriented image and a DEM: image <-> map
 ***************************************************************************/
#include "dem/monoplotter.h"

#include <algorithm>
#include <cmath>

namespace geostation
{

  Monoplotter::Monoplotter( const OrientedImage &image, const Dem &dem, const CrsTransform &blockToDem, const MonoplotOptions &options )
    : mImage( image ), mDem( dem ), mBlockToDem( blockToDem ), mOptions( options )
  {}

  std::optional<double> Monoplotter::demHeightAt( const Eigen::Vector3d &pointInWorld ) const
  {
    const Eigen::Vector3d q = mBlockToDem.transform( pointInWorld );
    return mDem.heightAt( q.x(), q.y() );
  }

  std::optional<Eigen::Vector3d> Monoplotter::hit( const OrientedImage &image, const Eigen::Vector2d &pixel, double demShiftM, DemIntersection *out ) const
  {
    std::optional<Ray> ray = image.worldRayFromPixel( pixel );
    if ( !ray )
    {
      if ( out )
      {
        out->status = DemIntersection::Status::Miss;
        out->message = "the pixel lies where the lens model cannot be inverted";
      }
      return std::nullopt;
    }
    // Raising the DEM by s is lowering the ray by s.
    ray->origin.z() -= demShiftM;
    DemIntersection result = intersectRayWithDem( *ray, mDem, mBlockToDem, mOptions.intersection );
    result.point.z() += demShiftM;
    if ( out )
      *out = result;
    if ( !result.hit() )
      return std::nullopt;
    return result.point;
  }

  MonoplotPoint Monoplotter::imageToGround( const Eigen::Vector2d &pixelInImage, bool precision ) const
  {
    MonoplotPoint p;
    p.pixelInImage = pixelInImage;
    DemIntersection first;
    const std::optional<Eigen::Vector3d> point = hit( mImage, pixelInImage, 0.0, &first );
    p.status = first.status;
    p.message = first.message;
    if ( !point )
      return p;
    p.world = *point;
    p.rangeM = first.rangeM;
    {
      const Eigen::Vector3d q = mBlockToDem.transform( *point );
      p.bridgeSigmaM = mDem.bridgeSigmaAt( q.x(), q.y() ).value_or( 0.0 );
    }
    if ( !precision )
      return p;

    // Propagation by central differences: pixel (col, row), DEM height and
    // the six exterior values, each with its sigma.
    Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
    const auto add = [&]( const std::optional<Eigen::Vector3d> &plus, const std::optional<Eigen::Vector3d> &minus, double step, double sigma )
    {
      if ( !( sigma > 0.0 ) )
        return true;
      if ( !plus || !minus )
        return false;
      const Eigen::Vector3d derivative = ( *plus - *minus ) / ( 2.0 * step );
      covariance += sigma * sigma * derivative * derivative.transpose();
      return true;
    };
    bool complete = true;
    const double pixelStep = 0.25;
    for ( int k = 0; k < 2; ++k )
    {
      Eigen::Vector2d delta = Eigen::Vector2d::Zero();
      delta[k] = pixelStep;
      complete &= add( hit( mImage, pixelInImage + delta, 0.0 ), hit( mImage, pixelInImage - delta, 0.0 ), pixelStep, mOptions.pixelSigmaPx );
    }
    const double demStep = 0.05;
    // (the DEM's own sigma and, where holes were bridged, the bridged cells')
    complete &= add( hit( mImage, pixelInImage, demStep ), hit( mImage, pixelInImage, -demStep ), demStep, std::hypot( mOptions.demSigmaM, p.bridgeSigmaM ) );
    const std::optional<ExteriorSigma> &sigma = mImage.exterior().sigma;
    if ( mOptions.propagateExterior && sigma )
    {
      const double sigmas[6] = { sigma->x, sigma->y, sigma->z, sigma->omegaDeg, sigma->phiDeg, sigma->kappaDeg };
      const double steps[6] = { 0.01, 0.01, 0.01, 1e-3, 1e-3, 1e-3 };
      for ( int k = 0; k < 6; ++k )
      {
        if ( !( sigmas[k] > 0.0 ) )
          continue;
        std::optional<Eigen::Vector3d> ends[2];
        for ( int side = 0; side < 2; ++side )
        {
          ExteriorOrientation eo = mImage.exterior();
          const double d = side == 0 ? steps[k] : -steps[k];
          double *values[6] = { &eo.projectionCentre.x(), &eo.projectionCentre.y(), &eo.projectionCentre.z(), &eo.omegaDeg, &eo.phiDeg, &eo.kappaDeg };
          *values[k] += d;
          ends[side] = hit( mImage.withExterior( eo ), pixelInImage, 0.0 );
        }
        complete &= add( ends[0], ends[1], steps[k], sigmas[k] );
      }
    }
    if ( !complete )
      p.message = "the precision is incomplete: a neighbouring ray misses the DEM";
    p.covariance = covariance;
    p.sigmaM = covariance.diagonal().cwiseSqrt();
    return p;
  }

  MapPointInImage Monoplotter::groundToImage( const Eigen::Vector3d &pointInWorld ) const
  {
    MapPointInImage result;
    result.projection = mImage.projectGroundToPixel( pointInWorld );
    if ( !result.projection.ok() || !result.projection.inFrame )
      return result;
    const Eigen::Vector3d centre = mImage.exterior().projectionCentre;
    const double distance = ( pointInWorld - centre ).norm();
    const DemIntersection first = intersectRayWithDem( { centre, ( pointInWorld - centre ) / distance }, mDem, mBlockToDem, mOptions.intersection );
    const double tolerance = std::max( 0.02, 1e-4 * distance );
    // Hidden when the terrain is met clearly before the point; a camera below
    // the terrain sees nothing.
    result.visible = first.status != DemIntersection::Status::BelowSurface && !( first.hit() && first.rangeM < distance - tolerance );
    return result;
  }

  std::vector<MonoplotPoint> Monoplotter::imageLineToGround( const std::vector<Eigen::Vector2d> &vertices, double densifyPx, bool precision ) const
  {
    if ( !( densifyPx > 0.0 ) )
      throw std::invalid_argument( "imageLineToGround: densifyPx must be positive" );
    std::vector<MonoplotPoint> out;
    for ( size_t i = 0; i < vertices.size(); ++i )
    {
      if ( i + 1 == vertices.size() )
      {
        out.push_back( imageToGround( vertices[i], precision ) );
        break;
      }
      const Eigen::Vector2d a = vertices[i], b = vertices[i + 1];
      const int pieces = std::max( 1, static_cast<int>( std::ceil( ( b - a ).norm() / densifyPx ) ) );
      for ( int k = 0; k < pieces; ++k )
        out.push_back( imageToGround( a + ( b - a ) * ( static_cast<double>( k ) / pieces ), precision ) );
    }
    return out;
  }

  std::vector<MapPointInImage> Monoplotter::groundLineToImage( const std::vector<Eigen::Vector3d> &vertices, double densifyPx, bool drape ) const
  {
    std::vector<MapPointInImage> out;
    const auto demHeight = [this]( const Eigen::Vector3d & p ) { return demHeightAt( p ); };
    for ( const Eigen::Vector3d &p : densifyForImage( mImage, vertices, densifyPx, drape ? std::function<std::optional<double>( const Eigen::Vector3d & )>( demHeight ) : nullptr ) )
      out.push_back( groundToImage( p ) );
    return out;
  }

  std::vector<std::pair<size_t, size_t>> resolvedRuns( const std::vector<MonoplotPoint> &line )
  {
    std::vector<std::pair<size_t, size_t>> runs;
    for ( size_t i = 0; i < line.size(); )
    {
      if ( !line[i].ok() )
      {
        ++i;
        continue;
      }
      size_t last = i;
      while ( last + 1 < line.size() && line[last + 1].ok() )
        ++last;
      if ( last > i )
        runs.emplace_back( i, last );
      i = last + 1;
    }
    const auto length = [&line]( const std::pair<size_t, size_t> &run )
    {
      double sum = 0.0;
      for ( size_t k = run.first; k < run.second; ++k )
        sum += ( line[k + 1].world - line[k].world ).norm();
      return sum;
    };
    std::stable_sort( runs.begin(), runs.end(), [&]( const auto &a, const auto &b ) { return length( a ) > length( b ); } );
    return runs;
  }

  GroundPointViewer featureViewer( const OrientedImage &image, const Monoplotter *monoplotter )
  {
    if ( monoplotter )
      return [monoplotter]( const Eigen::Vector3d &ground ) {
        const MapPointInImage seen = monoplotter->groundToImage( ground );
        return GroundPointView { seen.projection, seen.visible };
      };
    return [image]( const Eigen::Vector3d &ground ) { return GroundPointView { image.projectGroundToPixel( ground ), true }; };
  }

} // namespace geostation
