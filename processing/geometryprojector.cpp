/***************************************************************************
  geometryprojector.cpp - a map geometry into one image, for project_to_image
 ***************************************************************************/
#include "geometryprojector.h"

#include <cmath>

#include <QObject>
#include <qgscoordinatereferencesystem.h>
#include <qgsexception.h>

#include "geometrymapper.h"

namespace GeoStationProcessing
{
  namespace
  {
    std::unique_ptr<QgsLineString> toImageLine( const std::vector<Eigen::Vector2d> &part )
    {
      QVector<QgsPoint> points;
      for ( const Eigen::Vector2d &v : part )
        points << QgsPoint( v.x(), -v.y() );
      return std::make_unique<QgsLineString>( points );
    }
  } // namespace

  GeometryProjector::GeometryProjector( const geostation::OrientedImage &image, const geostation::Monoplotter *monoplotter, const QgsCoordinateTransform &toBlock,
                                        double densifyPx, bool drapeLines )
    : mImage( image )
    , mMonoplotter( monoplotter )
    , mToBlock( toBlock )
    , mView( geostation::featureViewer( image, monoplotter ) )
  {
    mLineOptions.densifyPx = densifyPx;
    if ( drapeLines && monoplotter )
      mLineOptions.heightAt = [monoplotter]( const Eigen::Vector3d & p ) { return monoplotter->demHeightAt( p ); };
  }

  //! A vertex in the block CRS, with its height (from the DEM when it has none).
  Eigen::Vector3d GeometryProjector::groundOf( const QgsPoint &vertex, QgsFeatureId id ) const
  {
    double x = vertex.x(), y = vertex.y(), z = vertex.z();
    const bool drape = std::isnan( z );
    if ( drape && !mMonoplotter )
      throw FeatureProblem { QStringLiteral( "no_height" ), QObject::tr( "Feature %1 has no Z value; without a DEM every vertex needs a height." ).arg( id ) };
    try
    {
      if ( drape )
        z = 0.0;
      mToBlock.transformInPlace( x, y, z );
    }
    catch ( const QgsCsException & )
    {
      throw FeatureProblem { QStringLiteral( "transform_failed" ), QObject::tr( "Feature %1 cannot be transformed from %2 to the block CRS %3." )
                             .arg( id ).arg( mToBlock.sourceCrs().userFriendlyIdentifier(), mToBlock.destinationCrs().userFriendlyIdentifier() ) };
    }
    if ( drape )
    {
      const std::optional<double> h = mMonoplotter->demHeightAt( Eigen::Vector3d( x, y, 0.0 ) );
      if ( !h )
        throw FeatureProblem { QStringLiteral( "outside_dem" ), QObject::tr( "Feature %1 has no Z value and lies outside the DEM." ).arg( id ) };
      z = *h;
    }
    return { x, y, z };
  }

  //! A point in the image; nothing when it cannot be projected.
  std::optional<QgsPoint> GeometryProjector::projectPoint( const Eigen::Vector3d &ground, geostation::FeatureProjectionTally &tally ) const
  {
    const geostation::GroundPointView v = mView( ground );
    tally.add( v );
    return v.projection.ok() ? std::optional<QgsPoint>( QgsPoint( v.projection.pixelInImage.x(), -v.projection.pixelInImage.y() ) ) : std::nullopt;
  }

  /**
   * A line or ring, densified, cut or clipped where it leaves the projectable
   * space. `otherParts`: where the other parts of a line cut into several go
   * (a multi-line keeps them all; a single line its longest, the first).
   */
  std::unique_ptr<QgsLineString> GeometryProjector::projectLine( const QgsLineString &line, QgsFeatureId id, geostation::FeatureProjectionTally &tally, bool closed,
      std::vector<std::unique_ptr<QgsLineString>> *otherParts ) const
  {
    std::vector<Eigen::Vector3d> ground;
    for ( int i = 0; i < line.numPoints(); ++i )
      ground.push_back( groundOf( line.pointN( i ), id ) );
    geostation::GroundLineOptions options = mLineOptions;
    options.closed = closed;
    const geostation::ProjectedGroundLine projected = geostation::projectGroundLine( mImage, ground, mView, options );
    tally.add( projected, !otherParts );
    if ( projected.parts.empty() )
      return nullptr;
    if ( otherParts )
      for ( size_t k = 1; k < projected.parts.size(); ++k )
        otherParts->push_back( toImageLine( projected.parts[k] ) );
    return toImageLine( projected.parts.front() );
  }

  std::unique_ptr<QgsAbstractGeometry> GeometryProjector::project( const QgsAbstractGeometry *geometry, QgsFeatureId id, geostation::FeatureProjectionTally &tally ) const
  {
    GeometryMapper mapper;
    mapper.point = [&]( const QgsPoint & p ) { return projectPoint( groundOf( p, id ), tally ); };
    mapper.line = [&]( const QgsLineString & line, bool closed ) { return projectLine( line, id, tally, closed ); };
    mapper.lineParts = [&]( const QgsLineString & line )
    {
      std::vector<std::unique_ptr<QgsLineString>> parts;
      if ( std::unique_ptr<QgsLineString> main = projectLine( line, id, tally, false, &parts ) )
        parts.insert( parts.begin(), std::move( main ) );
      else
        tally.clipped = true; // this part is out of the photo altogether
      return parts;
    };
    mapper.collectionType = []( QgsWkbTypes::Type type ) { return QgsWkbTypes::flatType( type ); }; // image space is 2D
    return mapGeometry( geometry, mapper );
  }

} // namespace GeoStationProcessing
