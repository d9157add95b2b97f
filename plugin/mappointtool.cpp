/***************************************************************************
  mappointtool.cpp - a map tool of the QGIS canvas that picks a point
 ***************************************************************************/
#include "mappointtool.h"

#include <QCursor>

#include <qgsmapcanvas.h>
#include <qgsmapmouseevent.h>

GeoStationMapPointTool::GeoStationMapPointTool( QgsMapCanvas *canvas, Qt::CursorShape cursor )
  : QgsMapTool( canvas )
{
  setCursor( QCursor( cursor ) );
}

void GeoStationMapPointTool::canvasReleaseEvent( QgsMapMouseEvent *e )
{
  if ( e->button() == Qt::LeftButton )
    emit picked( e->mapPoint() );
}
