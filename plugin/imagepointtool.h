/***************************************************************************
  imagepointtool.h - the map tool of an image view: pick a pixel
  -------------------------------------------------------------------------
  Only emits signals (as the georeferencer's tools do): a left click gives
  the pixel, a drag its start and end (to move a proposed point, or to give
  a traced line's direction); the mouse position is reported for the cursor
  readout. Pixels follow docs/conventions.md
  §1: the view shows the image at x = col, y = -row (x = -col in a view
  showing a photo mirrored as its EXIF tag asks).
 ***************************************************************************/
#ifndef GEOSTATIONIMAGEPOINTTOOL_H
#define GEOSTATIONIMAGEPOINTTOOL_H

#include <QPointF>

#include <qgsmaptool.h>
#include <qgspointxy.h>

#include "geometry/imagespace.h"

class GeoStationImagePointTool : public QgsMapTool
{
    Q_OBJECT

  public:
    explicit GeoStationImagePointTool( QgsMapCanvas *canvas );

    //! Pixel (col, row) of a point of the view's map; `mirrored`: the view shows the image at x = -col.
    static QPointF pixelFromMap( const QgsPointXY &point, bool mirrored = false )
    {
      const Eigen::Vector2d pixel = geostation::pixelOfImageSpace( Eigen::Vector2d( mirrored ? -point.x() : point.x(), point.y() ) );
      return QPointF( pixel.x(), pixel.y() );
    }
    static QgsPointXY mapFromPixel( double col, double row, bool mirrored = false )
    {
      const Eigen::Vector2d xy = geostation::imageSpaceOfPixel( Eigen::Vector2d( col, row ) );
      return QgsPointXY( mirrored ? -xy.x() : xy.x(), xy.y() );
    }

    //! The view shows the image mirrored (x = -col): its clicks are turned back into the stored pixels.
    void setMirrored( bool mirrored ) { mMirrored = mirrored; }

    void canvasMoveEvent( QgsMapMouseEvent *e ) override;
    void canvasPressEvent( QgsMapMouseEvent *e ) override;
    void canvasReleaseEvent( QgsMapMouseEvent *e ) override;

  signals:
    //! A left click.
    void pixelPicked( QPointF pixelInImage );
    //! A left drag, from where the button went down to where it came up.
    void pixelDragged( QPointF fromPixel, QPointF toPixel );
    void pixelHovered( QPointF pixelInImage );
    //! Right click: take back the last step.
    void undoRequested();

  private:
    bool mMirrored = false;
    bool mPressed = false;
    QPoint mPressScreen;
    QPointF mPressPixel;
};

#endif // GEOSTATIONIMAGEPOINTTOOL_H
