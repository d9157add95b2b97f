/***************************************************************************
  revisiondock.h - the Review Map Revision panel
  -------------------------------------------------------------------------
  Three layers chosen from the project - revise_roads' OUTPUT, its NEW
  roads and the map they revise - and the changes listed worst evidence
  first (revisionreview.h). Selecting a change zooms the map to it and
  selects it in its layer, and the Multiview shows its old and new course
  in the images that see it; Accept writes it into the map's edit buffer
  (a road not found flagged or deleted, as chosen), Reject leaves the map.
 ***************************************************************************/
#ifndef GEOSTATIONREVISIONDOCK_H
#define GEOSTATIONREVISIONDOCK_H

#include <memory>

#include <qgsdockwidget.h>

class QComboBox;
class QPushButton;
class QTableView;
class QgsCoordinateReferenceSystem;
class QgsGeometry;
class QgsMapCanvas;
class QgsMapLayerComboBox;
class GeoStationRevisionReview;

class GeoStationRevisionDock : public QgsDockWidget
{
    Q_OBJECT

  public:
    GeoStationRevisionDock( QgsMapCanvas *canvas, QWidget *parent = nullptr );
    ~GeoStationRevisionDock() override;

    //! The changes listed (null until layers are chosen).
    GeoStationRevisionReview *review() const { return mReview.get(); }

  signals:
    void message( const QString &text, bool warning );
    //! A change was selected: its map course and its new course, for the Multiview (revisionreview.h).
    void changeSelected( const QgsGeometry &oldCourse, const QgsGeometry &newCourse, const QgsCoordinateReferenceSystem &crs );

  private:
    void reload();
    void showCurrent();
    int currentRow() const;

    QgsMapCanvas *mCanvas = nullptr;
    QgsMapLayerComboBox *mRevisionLayer = nullptr, *mNewLayer = nullptr, *mMapLayer = nullptr;
    QComboBox *mNotFound = nullptr;
    QTableView *mTable = nullptr;
    QPushButton *mAccept = nullptr, *mReject = nullptr;
    std::unique_ptr<GeoStationRevisionReview> mReview;
};

#endif // GEOSTATIONREVISIONDOCK_H
