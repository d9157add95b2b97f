/***************************************************************************
  geometrymapper.cpp - rebuild a QGIS geometry vertex by vertex
 ***************************************************************************/
#include "geometrymapper.h"

#include <qgscurvepolygon.h>
#include <qgsexception.h>
#include <qgsgeometrycollection.h>
#include <qgsgeometryfactory.h>
#include <qgsmulticurve.h>
#include <qgspolygon.h>

namespace GeoStationProcessing
{

  std::unique_ptr<QgsAbstractGeometry> mapGeometry( const QgsAbstractGeometry *g, const GeometryMapper &mapper )
  {
    if ( const QgsPoint *point = qgsgeometry_cast<const QgsPoint *>( g ) )
    {
      const std::optional<QgsPoint> p = mapper.point( *point );
      return p ? std::make_unique<QgsPoint>( *p ) : nullptr;
    }
    if ( const QgsCurve *curve = qgsgeometry_cast<const QgsCurve *>( g ) )
    {
      const std::unique_ptr<QgsLineString> line( curve->curveToLine() );
      return mapper.line( *line, false );
    }
    if ( const QgsCurvePolygon *polygon = qgsgeometry_cast<const QgsCurvePolygon *>( g ) )
    {
      auto out = std::make_unique<QgsPolygon>();
      const auto ring = [&mapper]( const QgsCurve * curve )
      {
        const std::unique_ptr<QgsLineString> line( curve->curveToLine() );
        return mapper.line( *line, true );
      };
      std::unique_ptr<QgsLineString> exterior = ring( polygon->exteriorRing() );
      if ( !exterior )
        return nullptr;
      out->setExteriorRing( exterior.release() );
      for ( int i = 0; i < polygon->numInteriorRings(); ++i )
      {
        std::unique_ptr<QgsLineString> interior = ring( polygon->interiorRing( i ) );
        if ( !interior )
          return nullptr;
        out->addInteriorRing( interior.release() );
      }
      return out;
    }
    if ( const QgsGeometryCollection *collection = qgsgeometry_cast<const QgsGeometryCollection *>( g ) )
    {
      std::unique_ptr<QgsGeometryCollection> out( qgsgeometry_cast<QgsGeometryCollection *>(
            QgsGeometryFactory::geomFromWkbType( mapper.collectionType( collection->wkbType() ) ).release() ) );
      for ( int i = 0; i < collection->numGeometries(); ++i )
      {
        const QgsCurve *curve = qgsgeometry_cast<const QgsCurve *>( collection->geometryN( i ) );
        if ( curve && mapper.lineParts && qgsgeometry_cast<const QgsMultiCurve *>( collection ) )
        {
          const std::unique_ptr<QgsLineString> line( curve->curveToLine() );
          for ( std::unique_ptr<QgsLineString> &piece : mapper.lineParts( *line ) )
            out->addGeometry( piece.release() );
          continue;
        }
        std::unique_ptr<QgsAbstractGeometry> part = mapGeometry( collection->geometryN( i ), mapper );
        if ( !part )
          return nullptr;
        out->addGeometry( part.release() );
      }
      if ( out->isEmpty() )
        return nullptr;
      return out;
    }
    throw QgsProcessingException( QObject::tr( "Geometry type %1 is not supported." ).arg( QgsWkbTypes::displayString( g->wkbType() ) ) );
  }

}
