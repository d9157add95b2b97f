/***************************************************************************
  measurementstore.h - measured features into the GeoPackage (docs/conventions.md §7)
  -------------------------------------------------------------------------
  One layer per feature class (PointZ / LineStringZ / PolygonZ in the block
  CRS) with class, station, acquired, measured, n_images, sigma_x/y/z
  (worst vertex), method, measurement_id and the class's own attributes,
  and the companion table `vertices` (feature_fid, vertex, X, Y, Z, sx, sy,
  sz, image_ids, residuals_px, plus layer, method, measurement_id).

  Features go through the QGIS edit buffer: if the operator has the layer
  in edit mode the feature is added there (QGIS undo/redo, saved with the
  layer); otherwise it is committed at once. A commit that fails leaves the
  feature in the edit buffer and says why: nothing measured is lost. The
  vertex rows are written when their feature is committed (with its real
  fid), whenever that happens; if the store goes away first, they are
  written then, linked by measurement_id (see the destructor).
 ***************************************************************************/
#ifndef GEOSTATIONMEASUREMENTSTORE_H
#define GEOSTATIONMEASUREMENTSTORE_H

#include <QHash>
#include <QObject>
#include <QPointer>
#include <QVector>

#include <qgsfeature.h>
#include <qgsvectorlayer.h>

#include "featureclass.h"
#include "workstation/pointmeasurer.h"

class QgsProject;
class QgsVectorLayer;
class GeoStationMultiviewSession;

struct GeoStationMeasuredFeature
{
  QString className;
  QString station;   //!< station of the reference image
  QString acquired;  //!< its time
  QString measured;  //!< time of measurement (ISO 8601 UTC)
  QString measurementId;
  QVector<geostation::MeasuredVertex> vertices;
  //! Set for a feature not measured point by point ("traced"); otherwise method() is its vertices'.
  QString featureMethod;

  //! The feature's method: featureMethod, or the weakest of its vertices' (road-plane < monoplot-DEM < intersection).
  QString method() const;
  int imageCount() const;
};

class GeoStationMeasurementStore : public QObject
{
    Q_OBJECT

  public:
    GeoStationMeasurementStore( GeoStationMultiviewSession *session, QgsProject *project, QObject *parent = nullptr );

    /**
     * Writes the vertex rows of the features still in an edit buffer (not
     * yet saved, e.g. the disk was full) when the store goes away with the
     * plugin or QGIS: with an empty feature_fid, linked to their feature by
     * measurement_id, so the vertices survive however the edits are saved
     * later. Features the operator discarded get no rows.
     */
    ~GeoStationMeasurementStore() override;

    /**
     * Whether measurements can be written to the target GeoPackage (set,
     * folder writable, file writable if it exists, a GeoPackage if it
     * exists); false with one sentence.
     */
    bool checkWritable( QString *error ) const;

    //! Makes `path` the target GeoPackage if it can be written; otherwise keeps the old one and says why.
    bool setTarget( const QString &path, QString *error );

    /**
     * The layer of a class in the target GeoPackage, created (and added to
     * the project, group "GeoStation measurements") if needed; missing
     * attribute fields are added. nullptr with one sentence on failure.
     */
    QgsVectorLayer *layerFor( const GeoStationFeatureClass &featureClass, QString *error );
    QgsVectorLayer *verticesTable( QString *error );

    //! The measurement layers of the project that live in the target GeoPackage.
    QList<QgsVectorLayer *> measurementLayers() const;

    struct Result
    {
      bool ok = false;        //!< in the layer (committed, or in the operator's edit session)
      bool committed = false; //!< written to the file
      QString message;        //!< why not, or what happened
    };

    //! Adds a finished feature; see the class comment.
    Result addFeature( const GeoStationMeasuredFeature &feature );

    static QgsFields featureFields( const GeoStationFeatureClass &featureClass );
    static QgsFields vertexFields();

  signals:
    //! A measurement layer was added to the project or its features changed.
    void measurementsChanged();

  private:
    void watch( QgsVectorLayer *layer );
    void writeVertices( QgsVectorLayer *layer, const QgsFeatureList &added );
    //! Rows of the vertices table for each (feature fid, or null while the feature is unsaved; feature) of `layerName`.
    void writeVertexRows( const QString &layerName, const QList<QPair<QVariant, GeoStationMeasuredFeature>> &toWrite );
    QgsVectorLayer *openOrCreate( const QString &layerName, const QgsFields &fields, QgsWkbTypes::Type type, QString *error );

    GeoStationMultiviewSession *mSession;
    QgsProject *mProject;
    //! measurement_id -> the feature's vertices, until the feature is committed
    QHash<QString, GeoStationMeasuredFeature> mPendingVertices;
    QList<QPointer<QgsVectorLayer>> mWatched;
};

#endif // GEOSTATIONMEASUREMENTSTORE_H
