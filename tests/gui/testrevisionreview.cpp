// Reviewing a map revision into the map (offscreen): the changes listed worst
// evidence first and the new roads after them; a moved road accepted is
// spliced into its map feature, a road not found flagged or deleted, a new
// road added - each in the map layer's edit buffer, undoable, and nothing in
// the map's file until it is saved; a rejected change leaves the map alone.
// The map is a GeoPackage in WGS 84, the revision in UTM.
#include <QTemporaryDir>
#include <QtTest/QtTest>

#include <qgsapplication.h>
#include <qgscoordinatetransform.h>
#include <qgsfeatureiterator.h>
#include <qgsgeometry.h>
#include <qgslinestring.h>
#include <qgsproject.h>
#include <qgsvectorfilewriter.h>
#include <qgsvectorlayer.h>
#include <qgsvectorlayereditbuffer.h>

#include <QPushButton>
#include <QTableView>

#include <qgsmaplayercombobox.h>

#include "revisiondock.h"
#include "revisionreview.h"

class TestRevisionReview : public QObject
{
    Q_OBJECT

  private slots:
    void initTestCase();
    void listsAcceptsUndoesAndRejects();
    void panelAcceptsTheSelectedChange();

  private:
    QgsGeometry utmLine( const QVector<QgsPoint> &points ) const { return QgsGeometry( new QgsLineString( points ) ); }
    QgsGeometry inUtm( const QgsGeometry &wgs84 ) const;
    QTemporaryDir mDir;
    QString mMapPath;
    QgsCoordinateReferenceSystem mUtm, mWgs84;
};

QgsGeometry TestRevisionReview::inUtm( const QgsGeometry &wgs84 ) const
{
  QgsGeometry g = wgs84;
  g.transform( QgsCoordinateTransform( mWgs84, mUtm, QgsProject::instance()->transformContext() ) );
  return g;
}

void TestRevisionReview::initTestCase()
{
  mUtm = QgsCoordinateReferenceSystem( QStringLiteral( "EPSG:32617" ) );
  mWgs84 = QgsCoordinateReferenceSystem( QStringLiteral( "EPSG:4326" ) );
  // the old map: road A along y = 4400000 from x = 500000 to 500400, road B further north
  QgsVectorLayer memory( QStringLiteral( "LineString?crs=EPSG:4326&field=name:string" ), QStringLiteral( "map" ), QStringLiteral( "memory" ) );
  const QgsCoordinateTransform toWgs84( mUtm, mWgs84, QgsProject::instance()->transformContext() );
  QgsFeatureList features;
  for ( const auto &[name, line] : QList<QPair<QString, QgsGeometry>> { { "A", utmLine( { { 500000, 4400000 }, { 500200, 4400000 }, { 500400, 4400000 } } ) },
                                                                          { "B", utmLine( { { 500000, 4400300 }, { 500400, 4400300 } } ) } } )
  {
    QgsGeometry g = line;
    g.transform( toWgs84 );
    QgsFeature f( memory.fields() );
    f.setAttributes( QgsAttributes() << name );
    f.setGeometry( g );
    features << f;
  }
  memory.dataProvider()->addFeatures( features );
  mMapPath = mDir.filePath( "map.gpkg" );
  QgsVectorFileWriter::SaveVectorOptions options;
  options.driverName = QStringLiteral( "GPKG" );
  QString error;
  QCOMPARE( QgsVectorFileWriter::writeAsVectorFormatV3( &memory, mMapPath, QgsProject::instance()->transformContext(), options, &error ),
            QgsVectorFileWriter::NoError );
}

void TestRevisionReview::listsAcceptsUndoesAndRejects()
{
  QgsVectorLayer map( mMapPath, QStringLiteral( "map" ), QStringLiteral( "ogr" ) );
  QVERIFY( map.isValid() );
  QgsFeatureId a = FID_NULL, b = FID_NULL;
  QgsFeature f;
  QgsFeatureIterator it = map.getFeatures();
  while ( it.nextFeature( f ) )
    ( f.attribute( "name" ).toString() == "A" ? a : b ) = f.id();
  const QgsGeometry oldA = map.getFeature( a ).geometry();

  // revise_roads' OUTPUT and NEW, in UTM: A confirmed up to x = 500150 and moved 20 m north beyond; B not found; one new road
  QgsVectorLayer revision( QStringLiteral( "LineStringZ?crs=EPSG:32617&field=name:string&field=source_fid:long&field=revision:string&field=evidence:double"
                                           "&field=shift_m:double&field=sigma_max:double" ), QStringLiteral( "revised" ), QStringLiteral( "memory" ) );
  QVERIFY( GeoStationRevisionReview::isRevisionLayer( &revision ) );
  const auto piece = [&]( const QString &name, QgsFeatureId source, const QString &status, double evidence, double shift, const QgsGeometry &g ) {
    QgsFeature p( revision.fields() );
    p.setAttributes( QgsAttributes() << name << source << status << evidence << shift << 0.1 );
    p.setGeometry( g );
    return p;
  };
  revision.dataProvider()->addFeatures( QgsFeatureList()
                                        << piece( "A", a, "confirmed", 0.98, 0.0, utmLine( { { 500000, 4400000, 200 }, { 500150, 4400000, 200 } } ) )
                                        << piece( "A", a, "moved", 0.9, 20.0, utmLine( { { 500160, 4400020, 201 }, { 500300, 4400020, 201 }, { 500390, 4400020, 201 } } ) )
                                        << piece( "B", b, "not_found", 0.6, 0.0, utmLine( { { 500000, 4400300, 200 }, { 500400, 4400300, 200 } } ) ) );
  QgsVectorLayer added( QStringLiteral( "LineStringZ?crs=EPSG:32617&field=line_id:integer&field=method:string" ), QStringLiteral( "new" ), QStringLiteral( "memory" ) );
  QgsFeature n( added.fields() );
  n.setAttributes( QgsAttributes() << 1 << "extracted" );
  n.setGeometry( utmLine( { { 500100, 4399900, 199 }, { 500100, 4399700, 198 } } ) );
  added.dataProvider()->addFeatures( QgsFeatureList() << n );

  GeoStationRevisionReview review( &revision, &added, &map );
  QCOMPARE( review.rowCount(), 3 );
  QCOMPARE( review.item( 0 ).change, QStringLiteral( "not_found" ) ); // the worst evidence first
  QCOMPARE( review.item( 1 ).change, QStringLiteral( "moved" ) );
  QCOMPARE( review.item( 2 ).change, QStringLiteral( "new" ) );
  QCOMPARE( review.data( review.index( 1, GeoStationRevisionReview::ShiftM ) ).toString(), QStringLiteral( "20.0" ) );

  // what the Multiview draws, in the revision's CRS: the map's course and the images' course
  const GeoStationRevisionReview::Courses moved = review.courses( 1 );
  QCOMPARE( moved.crs, mUtm );
  QVERIFY2( moved.oldCourse.distance( QgsGeometry::fromPointXY( QgsPointXY( 500400, 4400000 ) ) ) < 0.01, qPrintable( moved.oldCourse.asWkt( 1 ) ) );
  QVERIFY2( moved.newCourse.distance( QgsGeometry::fromPointXY( QgsPointXY( 500300, 4400020 ) ) ) < 0.01, qPrintable( moved.newCourse.asWkt( 1 ) ) );
  const GeoStationRevisionReview::Courses notFound = review.courses( 0 ), newRoad = review.courses( 2 );
  QVERIFY( !notFound.oldCourse.isNull() && notFound.newCourse.isNull() );
  QVERIFY( newRoad.oldCourse.isNull() && !newRoad.newCourse.isNull() );

  // the moved road: A now runs 20 m north beyond x = 500160, as before up to the vertex at x = 500000
  QVERIFY( review.accept( 1 ) );
  QVERIFY( map.isEditable() && map.isModified() );
  const QgsGeometry movedA = inUtm( map.getFeature( a ).geometry() );
  QVERIFY2( movedA.distance( QgsGeometry::fromPointXY( QgsPointXY( 500300, 4400020 ) ) ) < 0.01, qPrintable( movedA.asWkt( 1 ) ) );
  QVERIFY( movedA.distance( QgsGeometry::fromPointXY( QgsPointXY( 500000, 4400000 ) ) ) < 0.01 );
  QVERIFY( movedA.distance( QgsGeometry::fromPointXY( QgsPointXY( 500400, 4400000 ) ) ) < 0.01 ); // the map's own end beyond the new course
  QVERIFY( !review.accept( 1 ) ); // twice: nothing
  // nothing in the file yet
  QgsVectorLayer onDisk( mMapPath, QStringLiteral( "on disk" ), QStringLiteral( "ogr" ) );
  QVERIFY( onDisk.getFeature( a ).geometry().equals( oldA ) );
  // undo takes it back
  map.undoStack()->undo();
  QVERIFY( map.getFeature( a ).geometry().equals( oldA ) );

  // the road not found: flagged in a field the buffer adds, then (undone) deleted instead
  QVERIFY( review.accept( 0, GeoStationRevisionReview::NotFoundAction::Flag ) );
  QCOMPARE( map.getFeature( b ).attribute( "revision" ).toString(), QStringLiteral( "not_found" ) );
  map.undoStack()->undo();
  QCOMPARE( map.fields().lookupField( "revision" ), -1 );
  GeoStationRevisionReview again( &revision, &added, &map );
  QVERIFY( again.accept( 0, GeoStationRevisionReview::NotFoundAction::Delete ) );
  QVERIFY( !map.getFeature( b ).isValid() );
  QCOMPARE( map.featureCount(), 1LL );

  // the new road: added, in the map's CRS and geometry type
  QVERIFY( again.accept( 2 ) );
  QCOMPARE( map.featureCount(), 2LL );
  QgsFeature newest;
  QgsFeatureIterator added2 = map.getFeatures();
  while ( added2.nextFeature( f ) )
    if ( f.attribute( "name" ).isNull() )
      newest = f;
  QCOMPARE( newest.geometry().wkbType(), map.wkbType() );
  QVERIFY( inUtm( newest.geometry() ).distance( QgsGeometry::fromPointXY( QgsPointXY( 500100, 4399800 ) ) ) < 0.01 );

  // rejecting writes nothing
  const long long edits = map.undoStack()->count();
  again.reject( 1 );
  QCOMPARE( again.item( 1 ).decision, QStringLiteral( "rejected" ) );
  QCOMPARE( map.undoStack()->count(), edits );
  map.rollBack();
  QCOMPARE( onDisk.featureCount(), 2LL );
}

void TestRevisionReview::panelAcceptsTheSelectedChange()
{
  QgsVectorLayer *map = new QgsVectorLayer( mMapPath, QStringLiteral( "map" ), QStringLiteral( "ogr" ) );
  QgsVectorLayer *revision = new QgsVectorLayer( QStringLiteral( "LineStringZ?crs=EPSG:32617&field=source_fid:long&field=revision:string&field=evidence:double&field=shift_m:double" ),
                                                 QStringLiteral( "revised" ), QStringLiteral( "memory" ) );
  QgsFeature gone( revision->fields() );
  QgsFeature first;
  map->getFeatures().nextFeature( first );
  gone.setAttributes( QgsAttributes() << first.id() << "not_found" << 0.7 << 0.0 );
  gone.setGeometry( utmLine( { { 500000, 4400000, 200 }, { 500400, 4400000, 200 } } ) );
  revision->dataProvider()->addFeatures( QgsFeatureList() << gone );
  QgsProject::instance()->addMapLayers( { map, revision } );

  GeoStationRevisionDock dock( nullptr );
  const QList<QgsMapLayerComboBox *> combos = dock.findChildren<QgsMapLayerComboBox *>();
  QCOMPARE( combos.size(), 3 ); // revision, new roads, map
  combos[0]->setLayer( revision );
  combos[1]->setLayer( nullptr );
  combos[2]->setLayer( map );
  QVERIFY( dock.review() );
  QCOMPARE( dock.review()->rowCount(), 1 );
  QTableView *table = dock.findChild<QTableView *>();
  QSignalSpy shown( &dock, &GeoStationRevisionDock::changeSelected );
  table->selectRow( 0 );
  QCOMPARE( shown.count(), 1 ); // to the Multiview: the road not found, its map course only
  QVERIFY( !shown.at( 0 ).at( 0 ).value<QgsGeometry>().isNull() );
  QVERIFY( shown.at( 0 ).at( 1 ).value<QgsGeometry>().isNull() );
  QPushButton *accept = nullptr;
  for ( QPushButton *button : dock.findChildren<QPushButton *>() )
    if ( button->text() == QStringLiteral( "Accept" ) )
      accept = button;
  QVERIFY( accept && accept->isEnabled() );
  accept->click();
  QCOMPARE( map->getFeature( first.id() ).attribute( "revision" ).toString(), QStringLiteral( "not_found" ) ); // flagged, the default
  QCOMPARE( dock.review()->item( 0 ).decision, QStringLiteral( "accepted" ) );
  map->rollBack();
  QgsProject::instance()->removeAllMapLayers();
}

int main( int argc, char **argv )
{
  QgsApplication app( argc, argv, true );
  QgsApplication::init();
  QgsApplication::initQgis();
  int result = 0;
  {
    TestRevisionReview test;
    result = QTest::qExec( &test, argc, argv );
  }
  QgsApplication::exitQgis();
  return result;
}

#include "testrevisionreview.moc"
