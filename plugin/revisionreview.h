/***************************************************************************
  revisionreview.h - the changes of a map revision, reviewed into the map
  -------------------------------------------------------------------------
  geostation:revise_roads writes the map's features split by what the
  pair shows (revision, evidence, shift_m, source_fid) and the new roads.
  This model lists the changes - the moved and not-found stretches, worst
  evidence first, then the new roads - and writes an accepted one into the
  map layer through its edit buffer, one undoable command each:

    moved      the map feature's stretch replaced by the new course
               (spliceCourse(): from where the course's ends meet it);
    not_found  the feature flagged (a `revision` field, added to the
               buffer when missing) or deleted, as the operator chooses;
    new        a feature added with the new road's course.

  Rejecting leaves the map as it is. Nothing reaches the map's file until
  the operator saves the layer; undo takes an acceptance back.
 ***************************************************************************/
#ifndef GEOSTATIONREVISIONREVIEW_H
#define GEOSTATIONREVISIONREVIEW_H

#include <QAbstractTableModel>
#include <QPointer>

#include <qgsfeatureid.h>
#include <qgscoordinatereferencesystem.h>
#include <qgsgeometry.h>

class QgsVectorLayer;

class GeoStationRevisionReview : public QAbstractTableModel
{
    Q_OBJECT

  public:
    enum Column
    {
      Change,
      Evidence,
      ShiftM,
      LengthM,
      Decision,
      ColumnCount
    };

    //! What accepting a road that was not found does to its map feature.
    enum class NotFoundAction
    {
      Flag,
      Delete,
    };

    struct Item
    {
      QString change;              //!< "moved", "not_found" or "new"
      QgsVectorLayer *layer = nullptr; //!< the revision layer, or the new roads' layer
      QgsFeatureId fid = FID_NULL; //!< in `layer`
      QgsFeatureId mapFid = FID_NULL; //!< the map feature it revises (moved, not_found)
      double evidence = -1.0;      //!< -1 for a new road
      double shiftM = 0.0, lengthM = 0.0;
      QString decision;            //!< "", "accepted", "rejected"
    };

    //! `revision`: revise_roads' OUTPUT; `newRoads`: its NEW (may be null); `map`: the map layer revised.
    GeoStationRevisionReview( QgsVectorLayer *revision, QgsVectorLayer *newRoads, QgsVectorLayer *map, QObject *parent = nullptr );

    //! A layer written by geostation:revise_roads' OUTPUT (revision, evidence, shift_m, source_fid).
    static bool isRevisionLayer( const QgsVectorLayer *layer );

    int rowCount( const QModelIndex &parent = QModelIndex() ) const override;
    int columnCount( const QModelIndex &parent = QModelIndex() ) const override;
    QVariant data( const QModelIndex &index, int role = Qt::DisplayRole ) const override;
    QVariant headerData( int section, Qt::Orientation orientation, int role = Qt::DisplayRole ) const override;

    const Item &item( int row ) const { return mItems.at( row ); }

    //! The change's course in the map layer's CRS (what to show and zoom to).
    QgsGeometry geometryInMapCrs( int row ) const;

    //! A change's two courses in `crs` (the revision layer's, the block CRS): null where it has none.
    struct Courses
    {
      QgsGeometry oldCourse; //!< the map's: a moved road's map feature, the road not found
      QgsGeometry newCourse; //!< the images': a moved road's new course, a new road
      QgsCoordinateReferenceSystem crs;
    };
    //! What the Multiview draws for a change.
    Courses courses( int row ) const;

    /**
     * Writes the change into the map layer's edit buffer (editing is
     * started when it is not), as one undoable command. False with a
     * message when nothing was written.
     */
    bool accept( int row, NotFoundAction notFound = NotFoundAction::Flag );

    //! Leaves the map as it is and records the decision.
    void reject( int row );

  signals:
    void message( const QString &text, bool warning );

  private:
    void load();
    bool acceptMoved( int row );
    bool acceptNotFound( const Item &item, NotFoundAction action );
    bool acceptNew( int row );
    void decide( int row, const QString &decision );

    QPointer<QgsVectorLayer> mRevision, mNewRoads, mMap;
    QList<Item> mItems;
};

#endif // GEOSTATIONREVISIONREVIEW_H
