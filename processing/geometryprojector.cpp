/***************************************************************************
  geometryprojector.cpp - a map geometry into one image, for project_to_image
 ***************************************************************************/
#include "geometryprojector.h"

#include <cmath>
#include <limits>

#include <QObject>
#include <qgscoordinatereferencesystem.h>
#include <qgsexception.h>
#include <qgsvertexid.h>

#include "geometry/imagespace.h"
#include "geometrymapper.h"

namespace GeoStationProcessing
{
  namespace
  {
    std::unique_ptr<QgsLineString> toImageLine( const std::vector<Eigen::Vector2d> &part )
    {
      QVector<QgsPoint> points;
      for ( const Eigen::Vector2d &v : part )
      {
        const Eigen::Vector2d xy = geostation::imageSpaceOfPixel( v );
        points << QgsPoint( xy.x(), xy.y() );
      }
      return std::make_unique<QgsLineString>( points );
    }
  } // namespace

  GeometryProjector::GeometryProjector( const geostation::OrientedImage &image, const geostation::Monoplotter *monoplotter, const QgsCoordinateTransform &toBlock,
                                        double densifyPx )
    : mImage( image )
    , mToBlock( toBlock )
    , mDensifyPx( densifyPx )
  {
    mHeights.dem = monoplotter; // the feature's Z, else the DEM's height; no plane: a vertex without either is refused
  }

  //! A part's vertices in the block CRS with their heights by the rule; throws FeatureProblem for a vertex that cannot have one.
  geostation::GroundPart GeometryProjector::groundOf( const QgsAbstractGeometry &part, QgsFeatureId id ) const
  {
    std::vector<Eigen::Vector3d> vertices;
    QgsVertexId v;
    QgsPoint p;
    while ( part.nextVertex( v, p ) )
    {
      double x = p.x(), y = p.y(), z = p.z();
      const bool noZ = std::isnan( z );
      try
      {
        if ( noZ )
          z = 0.0;
        mToBlock.transformInPlace( x, y, z );
      }
      catch ( const QgsCsException & )
      {
        throw FeatureProblem { QStringLiteral( "transform_failed" ), QObject::tr( "Feature %1 cannot be transformed from %2 to the block CRS %3." )
                               .arg( id ).arg( mToBlock.sourceCrs().userFriendlyIdentifier(), mToBlock.destinationCrs().userFriendlyIdentifier() ) };
      }
      vertices.emplace_back( x, y, noZ ? std::numeric_limits<double>::quiet_NaN() : z );
    }
    geostation::GroundPart ground = geostation::groundPart( vertices, mHeights );
    switch ( ground.status )
    {
      case geostation::FeatureHeightStatus::Ok:
        break;
      case geostation::FeatureHeightStatus::NoHeight:
        throw FeatureProblem { QStringLiteral( "no_height" ), QObject::tr( "Feature %1 has no Z value; without a DEM every vertex needs a height." ).arg( id ) };
      case geostation::FeatureHeightStatus::OutsideDem:
        throw FeatureProblem { QStringLiteral( "outside_dem" ), QObject::tr( "Feature %1 has no Z value and lies outside the DEM." ).arg( id ) };
    }
    return ground;
  }

  //! A point in the image; nothing when it cannot be projected.
  std::optional<QgsPoint> GeometryProjector::projectPoint( const QgsPoint &point, QgsFeatureId id, geostation::FeatureProjectionTally &tally ) const
  {
    const geostation::GroundPointView v = geostation::pointInPhoto( mImage, groundOf( point, id ).vertices.front(), mHeights );
    tally.add( v );
    if ( !v.projection.ok() )
      return std::nullopt;
    const Eigen::Vector2d xy = geostation::imageSpaceOfPixel( v.projection.pixelInImage );
    return QgsPoint( xy.x(), xy.y() );
  }

  /**
   * A line or ring, densified, cut or clipped where it leaves the projectable
   * space. `otherParts`: where the other parts of a line cut into several go
   * (a multi-line keeps them all; a single line its longest, the first).
   */
  std::unique_ptr<QgsLineString> GeometryProjector::projectLine( const QgsLineString &line, QgsFeatureId id, geostation::FeatureProjectionTally &tally, bool closed,
      std::vector<std::unique_ptr<QgsLineString>> *otherParts ) const
  {
    geostation::LineInPhotoOptions options;
    options.densifyPx = mDensifyPx;
    options.closed = closed;
    const geostation::ProjectedGroundLine projected = geostation::lineInPhoto( mImage, groundOf( line, id ), mHeights, options );
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
    mapper.point = [&]( const QgsPoint & p ) { return projectPoint( p, id, tally ); };
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
