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
  emit pixelHovered( pixelFromMap( e->mapPoint(), mMirrored ) );
}

void GeoStationImagePointTool::canvasPressEvent( QgsMapMouseEvent *e )
{
  mPressed = e->button() == Qt::LeftButton;
  mPressScreen = e->pos();
  mPressPixel = pixelFromMap( e->mapPoint(), mMirrored );
}

void GeoStationImagePointTool::canvasReleaseEvent( QgsMapMouseEvent *e )
{
  if ( e->button() == Qt::LeftButton )
  {
    // a drag of more than a few screen pixels, else a click
    if ( mPressed && ( e->pos() - mPressScreen ).manhattanLength() > 6 )
      emit pixelDragged( mPressPixel, pixelFromMap( e->mapPoint(), mMirrored ) );
    else
      emit pixelPicked( pixelFromMap( e->mapPoint(), mMirrored ) );
    mPressed = false;
  }
  else if ( e->button() == Qt::RightButton )
    emit undoRequested();
}
