/***************************************************************************
  imageview.h - one image panel of the Multiview
  -------------------------------------------------------------------------
  A QgsMapCanvas showing an image as a raster layer in pixel space
  (x = col, y = -row, as the georeferencer does), so tiling, overviews,
  zoom and pan are QGIS's. Over the image: the epipolar curves of a point
  clicked in another view, the proposed conjugate point with its score,
  the observation taken for the current vertex, and every measured feature
  projected into this image. The header chooses the image and the
  enhancement (computed in memory, the file is never rewritten). An image
  that cannot be shown is replaced by a placeholder saying why.
 ***************************************************************************/
#ifndef GEOSTATIONIMAGEVIEW_H
#define GEOSTATIONIMAGEVIEW_H

#include <memory>

#include <QPair>
#include <QPointF>
#include <QWidget>

#include <qgsgeometry.h>

#include "geometry/epipolar.h"

class QComboBox;
class QLabel;
class QStackedWidget;
class QgsMapCanvas;
class QgsRasterLayer;
class QgsRubberBand;
class QgsVertexMarker;
class GeoStationImagePointTool;

class GeoStationImageView : public QWidget
{
    Q_OBJECT

  public:
    GeoStationImageView( int index, QWidget *parent = nullptr );
    ~GeoStationImageView() override;

    int index() const { return mIndex; }
    QString imageId() const { return mImageId; }
    QgsMapCanvas *canvas() const { return mCanvas; }
    //! Whether the image is on screen (not the placeholder).
    bool hasImage() const;
    QString placeholderText() const;

    //! The images offered in the chooser (all images of the block).
    void setImageChoices( const QStringList &imageIds );

    /**
     * Shows an image file (empty id: nothing). `expectedWidth/Height` are the
     * camera's; a file that is missing, cannot be decoded or has another size
     * gives the placeholder with the reason. Keeps the zoom when the new
     * image has the size of the previous one.
     */
    void showImage( const QString &imageId, const QString &path, int expectedWidth, int expectedHeight );

    //! "" for the original, or an enhancement method name of core (e.g. "equalise").
    QString enhancement() const { return mEnhancement; }
    void setEnhancement( const QString &method );
    //! The enhancements offered: (name, label) pairs, the original first.
    static QList<QPair<QString, QString>> enhancementChoices();

    //! The grey value (or R,G,B) at a pixel, as text; "" outside the image.
    QString valueAt( const QPointF &pixelInImage ) const;

    /**
     * Clockwise degrees the view is turned by: a photo tagged to be shown
     * turned (EXIF orientation 3, 6, 8; 4, 5, 7 after the mirror) is shown
     * so, its pixels as stored.
     */
    int viewTurnDeg() const { return mTurnDeg; }
    /**
     * Whether the view shows the photo mirrored left to right (EXIF
     * orientation 2, 4, 5, 7; then turned by viewTurnDeg()): its map is then
     * x = -col, y = -row. Overlays go through mapFromPixel() or inView().
     */
    bool viewMirrored() const { return mMirrored; }
    //! The point of the view's map showing a pixel (col, row) of the stored image.
    QgsPointXY mapFromPixel( const QPointF &pixelInImage ) const;
    //! A geometry in x = col, y = -row, as the view shows it (mirrored with the photo).
    QgsGeometry inView( const QgsGeometry &pixelSpace ) const;

    //! Zooms so `halfWidthPx` image pixels either side of a pixel fill the view.
    void zoomToPixel( const QPointF &pixelInImage, double halfWidthPx );
    void zoomToFullImage();

    // ---- overlays (pixel coordinates) ----
    void setEpipolarCurves( const geostation::EpipolarCurve &curve );
    //! The proposed conjugate point and its score; `matched` false draws nothing but the status text.
    void setProposal( bool matched, const QPointF &pixelInImage, double score, const QString &status, bool doubtful = false );
    //! The observation taken for the vertex being measured (reference click or accepted/corrected point).
    void setObservation( bool present, const QPointF &pixelInImage, bool reference );
    void clearMeasurementOverlays();
    //! Measured features projected into this image (geometries in x = col, y = -row).
    void setFeatureOverlay( const QVector<QgsGeometry> &geometries );
    int featureOverlayCount() const { return mFeatureOverlayCount; }
    //! The line being traced, projected into this image (x = col, y = -row); null clears it.
    void setTraceOverlay( const QgsGeometry &geometry );
    //! Vertices of the traced line drawn in this view (tests).
    int traceOverlayVertexCount() const { return mTraceOverlayVertices; }
    /**
     * A map revision's change in this image (x = col, y = -row): the map's
     * old course dashed red, the course the images show green; null
     * geometries draw nothing (both null clear it).
     */
    void setChangeOverlay( const QgsGeometry &oldCourse, const QgsGeometry &newCourse );
    //! Vertices of the old and the new course drawn in this view (tests).
    QPair<int, int> changeOverlayVertexCounts() const { return mChangeOverlayVertices; }

  signals:
    void imageChosen( int view, const QString &imageId );
    void enhancementChosen( int view, const QString &method );
    void pixelPicked( int view, QPointF pixelInImage );
    void pixelDragged( int view, QPointF fromPixel, QPointF toPixel );
    void pixelHovered( int view, QPointF pixelInImage );
    void undoRequested();

  private:
    void showPlaceholder( const QString &reason );
    void updateLayer();
    void setStatus( const QString &text );

    int mIndex;
    QString mImageId, mPath, mEnhancement, mMemoryPath;
    int mWidth = 0, mHeight = 0;
    int mTurnDeg = 0;
    bool mMirrored = false;
    bool mLayerMirrored = false; //!< the layer updateLayer() made is at x = -col
    int mExifOrientation = 1; //!< of the file shown (updateLayer())
    QComboBox *mImageCombo = nullptr;
    QComboBox *mEnhancementCombo = nullptr;
    QLabel *mStatus = nullptr;
    QStackedWidget *mStack = nullptr;
    QLabel *mPlaceholder = nullptr;
    QgsMapCanvas *mCanvas = nullptr;
    GeoStationImagePointTool *mTool = nullptr;
    std::unique_ptr<QgsRasterLayer> mLayer;
    QgsRubberBand *mEpipolar = nullptr;
    QgsVertexMarker *mProposal = nullptr;
    QgsVertexMarker *mObservation = nullptr;
    QgsRubberBand *mOverlayLines = nullptr;
    QgsRubberBand *mOverlayPoints = nullptr;
    int mFeatureOverlayCount = 0;
    QgsRubberBand *mTraceOverlay = nullptr;
    int mTraceOverlayVertices = 0;
    QgsRubberBand *mOldCourse = nullptr, *mNewCourse = nullptr;
    QPair<int, int> mChangeOverlayVertices { 0, 0 };
};

#endif // GEOSTATIONIMAGEVIEW_H
