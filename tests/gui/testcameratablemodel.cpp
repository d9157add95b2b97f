// The camera table and the block information dialog, on the sample block.
#include <QTableView>
#include <QLabel>
#include <QtTest/QtTest>

#include "blockinfodialog.h"
#include "cameratablemodel.h"
#include "io/block.h"

class TestCameraTableModel : public QObject
{
    Q_OBJECT

  private slots:
    void initTestCase();
    void showsEveryCameraWithItsInteriorOrientation();
    void clearsWithoutABlock();
    void dialogSummarisesTheBlock();

  private:
    geostation::Block mBlock;
};

void TestCameraTableModel::initTestCase()
{
  mBlock = geostation::Block::load( std::string( GEOSTATION_SOURCE_DIR ) + "/docs/examples/sample.geostation.json" );
}

void TestCameraTableModel::showsEveryCameraWithItsInteriorOrientation()
{
  GeoStationCameraTableModel model;
  model.setBlock( &mBlock );
  QCOMPARE( model.rowCount(), 3 );
  QCOMPARE( model.columnCount(), static_cast<int>( GeoStationCameraTableModel::ColumnCount ) );
  QCOMPARE( model.headerData( GeoStationCameraTableModel::ColumnF, Qt::Horizontal ).toString(), QStringLiteral( "f [px]" ) );

  const auto cell = [&model]( int row, int column, int role = Qt::DisplayRole ) { return model.data( model.index( row, column ), role ); };
  QCOMPARE( cell( 0, GeoStationCameraTableModel::ColumnId ).toString(), QStringLiteral( "left" ) );
  QCOMPARE( cell( 0, GeoStationCameraTableModel::ColumnSize ).toString(), QStringLiteral( "640 × 480" ) );
  QCOMPARE( cell( 0, GeoStationCameraTableModel::ColumnF ).toString(), QStringLiteral( "812.400" ) );
  QCOMPARE( cell( 0, GeoStationCameraTableModel::ColumnF, Qt::EditRole ).toDouble(), 812.4 );
  QCOMPARE( cell( 0, GeoStationCameraTableModel::ColumnModel ).toString(), QStringLiteral( "opencv" ) );
  QCOMPARE( cell( 0, GeoStationCameraTableModel::ColumnK1, Qt::EditRole ).toDouble(), -0.21 );
  QCOMPARE( cell( 0, GeoStationCameraTableModel::ColumnImages ).toInt(), 2 );
  QCOMPARE( cell( 1, GeoStationCameraTableModel::ColumnModel ).toString(), QStringLiteral( "brown_photo" ) );
  QCOMPARE( cell( 1, GeoStationCameraTableModel::ColumnP2, Qt::EditRole ).toDouble(), -2.0e-5 );
  QCOMPARE( cell( 1, GeoStationCameraTableModel::ColumnImages ).toInt(), 1 );
  // no lens model: no coefficients shown, no pixel size given
  QCOMPARE( cell( 2, GeoStationCameraTableModel::ColumnModel ).toString(), QStringLiteral( "none" ) );
  QVERIFY( cell( 2, GeoStationCameraTableModel::ColumnK1 ).isNull() );
  QVERIFY( cell( 2, GeoStationCameraTableModel::ColumnPixelSize ).isNull() );
  QCOMPARE( cell( 2, GeoStationCameraTableModel::ColumnImages ).toInt(), 0 );
  QVERIFY( !cell( 3, 0 ).isValid() );
}

void TestCameraTableModel::clearsWithoutABlock()
{
  GeoStationCameraTableModel model;
  model.setBlock( &mBlock );
  QSignalSpy reset( &model, &QAbstractItemModel::modelReset );
  model.setBlock( nullptr );
  QCOMPARE( reset.count(), 1 );
  QCOMPARE( model.rowCount(), 0 );
}

void TestCameraTableModel::dialogSummarisesTheBlock()
{
  GeoStationBlockInfoDialog dialog( mBlock );
  QCOMPARE( GeoStationBlockInfoDialog::contentsSummary( mBlock ), QStringLiteral( "3 cameras, 2 stations, 3 images (2 oriented)" ) );
  QLabel *crs = dialog.findChild<QLabel *>( QStringLiteral( "mCrsLabel" ) );
  QVERIFY( crs );
  QCOMPARE( crs->text(), QStringLiteral( "EPSG:32617 — WGS 84 / UTM zone 17N" ) );
  QTableView *table = dialog.findChild<QTableView *>( QStringLiteral( "mCameraTable" ) );
  QVERIFY( table && table->model() );
  QCOMPARE( table->model()->rowCount(), 3 );
}

QTEST_MAIN( TestCameraTableModel )
#include "testcameratablemodel.moc"
