/***************************************************************************
  groundpoints.cpp - ground positions from QGIS layers for the orientation
 ***************************************************************************/
#include "groundpoints.h"

#include <cmath>

#include <qgscoordinatetransform.h>
#include <qgsfeatureiterator.h>
#include <qgsproject.h>
#include <qgsrasterdataprovider.h>
#include <qgsrasterlayer.h>
#include <qgsvectorlayer.h>

#include "multiviewsession.h"

namespace GeoStationGroundPoints
{
  ControlLayerPoints readControlLayer( QgsVectorLayer *layer, const GeoStationMultiviewSession *session )
  {
    const QgsFields fields = layer->fields();
    int idField = -1, zField = -1;
    for ( const QString &name : { QStringLiteral( "point_id" ), QStringLiteral( "id" ), QStringLiteral( "name" ) } )
      if ( idField < 0 )
        idField = fields.lookupField( name );
    for ( const QString &name : { QStringLiteral( "Z" ), QStringLiteral( "height" ), QStringLiteral( "elevation" ) } )
      if ( zField < 0 )
        zField = fields.lookupField( name );
    const QgsCoordinateTransform toBlock( layer->crs(), session->crs(), QgsProject::instance() );
    ControlLayerPoints result;
    QgsFeature f;
    QgsFeatureIterator it = layer->getFeatures();
    while ( it.nextFeature( f ) )
    {
      const QgsGeometry geometry = f.geometry();
      if ( geometry.isNull() || geometry.isEmpty() )
        continue;
      const QgsPoint point = geometry.vertexAt( 0 );
      QgsPointXY xy;
      try
      {
        xy = toBlock.transform( QgsPointXY( point.x(), point.y() ) );
      }
      catch ( const QgsCsException & )
      {
        continue;
      }
      std::optional<double> z;
      if ( point.is3D() && std::isfinite( point.z() ) )
        z = point.z();
      else if ( zField >= 0 && !f.attribute( zField ).isNull() )
        z = f.attribute( zField ).toDouble();
      else
      {
        QString why;
        z = demHeight( session, xy, &why );
      }
      if ( !z )
      {
        ++result.withoutHeight;
        continue;
      }
      const QString id = idField >= 0 ? f.attribute( idField ).toString() : QString::number( f.id() );
      result.points.append( qMakePair( id, Eigen::Vector3d( xy.x(), xy.y(), *z ) ) );
    }
    return result;
  }

  std::optional<double> demHeight( const GeoStationMultiviewSession *session, const QgsPointXY &pointInBlockCrs, QString *why )
  {
    QgsRasterLayer *dem = qobject_cast<QgsRasterLayer *>( QgsProject::instance()->mapLayer( session->demLayerId() ) );
    if ( !dem || !dem->dataProvider() )
    {
      *why = QObject::tr( "no DEM layer is set (GeoStation ▸ Measurement Settings)" );
      return std::nullopt;
    }
    try
    {
      const QgsPointXY inDem = QgsCoordinateTransform( session->crs(), dem->crs(), QgsProject::instance() ).transform( pointInBlockCrs );
      bool ok = false;
      const double height = dem->dataProvider()->sample( inDem, 1, &ok );
      if ( ok && std::isfinite( height ) )
        return height;
    }
    catch ( const QgsCsException & )
    {
    }
    *why = QObject::tr( "the point is outside the DEM %1 or on a hole in it" ).arg( dem->name() );
    return std::nullopt;
  }
} // namespace GeoStationGroundPoints
