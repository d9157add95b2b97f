/***************************************************************************
  stationpicktool.cpp - the Overview's station-picking map tool
 ***************************************************************************/
#include "stationpicktool.h"

#include <QCursor>

#include <qgsmapcanvas.h>
#include <qgsmapmouseevent.h>

GeoStationStationPickTool::GeoStationStationPickTool( QgsMapCanvas *canvas )
  : QgsMapTool( canvas )
{
  setCursor( QCursor( Qt::PointingHandCursor ) );
}

void GeoStationStationPickTool::canvasReleaseEvent( QgsMapMouseEvent *e )
{
  if ( e->button() == Qt::LeftButton )
    emit picked( e->mapPoint() );
}
