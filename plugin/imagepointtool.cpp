/***************************************************************************
  imagepointtool.cpp
 ***************************************************************************/
#include "imagepointtool.h"

#include <qgsmapmouseevent.h>

GeoStationImagePointTool::GeoStationImagePointTool( QgsMapCanvas *canvas )
  : QgsMapTool( canvas )
{
  setCursor( QCursor( Qt::CrossCursor ) );
}

void GeoStationImagePointTool::canvasMoveEvent( QgsMapMouseEvent *e )
{
  emit pixelHovered( pixelFromMap( e->mapPoint() ) );
}

void GeoStationImagePointTool::canvasReleaseEvent( QgsMapMouseEvent *e )
{
  if ( e->button() == Qt::LeftButton )
    emit pixelPicked( pixelFromMap( e->mapPoint() ) );
  else if ( e->button() == Qt::RightButton )
    emit undoRequested();
}
