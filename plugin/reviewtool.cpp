/***************************************************************************
  reviewtool.cpp - the map tool that accepts or rejects extracted lines
 ***************************************************************************/
#include "reviewtool.h"

#include <qgscoordinatetransform.h>
#include <qgsexception.h>
#include <qgsgeometry.h>
#include <qgsmapcanvas.h>
#include <qgsmapmouseevent.h>
#include <qgsvectorlayer.h>

#include "extractionreview.h"

GeoStationReviewTool::GeoStationReviewTool( QgsMapCanvas *canvas )
  : QgsMapTool( canvas )
{
}

bool GeoStationReviewTool::lineAt( QgsMapCanvas *canvas, const QgsPointXY &pointInCanvasCrs, double radius, QgsVectorLayer *&layer, QgsFeatureId &fid )
{
  double best = radius;
  bool found = false;
  const QgsGeometry point = QgsGeometry::fromPointXY( pointInCanvasCrs );
  for ( QgsMapLayer *l : canvas->layers() )
  {
    QgsVectorLayer *candidate = qobject_cast<QgsVectorLayer *>( l );
    if ( !GeoStationExtractionReview::isExtractedRoadsLayer( candidate ) )
      continue;
    const QgsCoordinateTransform toCanvas( candidate->crs(), canvas->mapSettings().destinationCrs(), candidate->transformContext() );
    const QgsRectangle search( pointInCanvasCrs.x() - radius, pointInCanvasCrs.y() - radius, pointInCanvasCrs.x() + radius, pointInCanvasCrs.y() + radius );
    QgsFeatureRequest request;
    try
    {
      request.setFilterRect( toCanvas.transformBoundingBox( search, Qgis::TransformDirection::Reverse ) ).setNoAttributes();
    }
    catch ( const QgsCsException & )
    {
      continue; // the click is outside the layer's CRS area
    }
    QgsFeature f;
    QgsFeatureIterator it = candidate->getFeatures( request );
    while ( it.nextFeature( f ) )
    {
      QgsGeometry g = f.geometry();
      try
      {
        if ( g.transform( toCanvas ) != Qgis::GeometryOperationResult::Success )
          continue;
      }
      catch ( const QgsCsException & )
      {
        continue;
      }
      const double d = g.distance( point );
      if ( d <= best )
      {
        best = d;
        layer = candidate;
        fid = f.id();
        found = true;
      }
    }
  }
  return found;
}

void GeoStationReviewTool::canvasReleaseEvent( QgsMapMouseEvent *e )
{
  if ( e->button() != Qt::LeftButton && e->button() != Qt::RightButton )
    return;
  QgsVectorLayer *layer = nullptr;
  QgsFeatureId fid = FID_NULL;
  if ( lineAt( canvas(), e->mapPoint(), searchRadiusMU( canvas() ), layer, fid ) )
    emit picked( layer, fid, e->button() == Qt::LeftButton );
  else
    emit missed();
}
