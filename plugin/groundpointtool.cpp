/***************************************************************************
  groundpointtool.cpp - a map tool of the QGIS canvas: pick a ground point
 ***************************************************************************/
#include "groundpointtool.h"

#include <QCursor>

#include <qgsmapcanvas.h>
#include <qgsmapmouseevent.h>

GeoStationGroundPointTool::GeoStationGroundPointTool( QgsMapCanvas *canvas )
  : QgsMapTool( canvas )
{
  setCursor( QCursor( Qt::CrossCursor ) );
}

void GeoStationGroundPointTool::canvasReleaseEvent( QgsMapMouseEvent *e )
{
  if ( e->button() == Qt::LeftButton )
    emit picked( e->mapPoint() );
}
