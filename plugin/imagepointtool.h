/***************************************************************************
  imagepointtool.h - the map tool of an image view: pick a pixel
  -------------------------------------------------------------------------
  Only emits signals (as the georeferencer's tools do): a left click (or
  the end of a drag, to move a proposed point) gives the pixel, the mouse
  position is reported for the cursor readout. Pixels follow CONVENTIONS
  §1: the view shows the image at x = col, y = -row.
 ***************************************************************************/
#ifndef GEOSTATIONIMAGEPOINTTOOL_H
#define GEOSTATIONIMAGEPOINTTOOL_H

#include <QPointF>

#include <qgsmaptool.h>
#include <qgspointxy.h>

class GeoStationImagePointTool : public QgsMapTool
{
    Q_OBJECT

  public:
    explicit GeoStationImagePointTool( QgsMapCanvas *canvas );

    //! Pixel (col, row) of a point of the view's map.
    static QPointF pixelFromMap( const QgsPointXY &point ) { return QPointF( point.x(), -point.y() ); }
    static QgsPointXY mapFromPixel( double col, double row ) { return QgsPointXY( col, -row ); }

    void canvasMoveEvent( QgsMapMouseEvent *e ) override;
    void canvasReleaseEvent( QgsMapMouseEvent *e ) override;

  signals:
    void pixelPicked( QPointF pixelInImage );
    void pixelHovered( QPointF pixelInImage );
    //! Right click: take back the last step.
    void undoRequested();
};

#endif // GEOSTATIONIMAGEPOINTTOOL_H
