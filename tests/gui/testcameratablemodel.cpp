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
  QCOMPARE( model.columnCount(), GeoStationCameraTableModel::kColumnCount );
  QCOMPARE( model.headerData( static_cast<int>( GeoStationCameraTableModel::Column::F ), Qt::Horizontal ).toString(), QStringLiteral( "f [px]" ) );

  using Column = GeoStationCameraTableModel::Column;
  const auto cell = [&model]( int row, Column column, int role = Qt::DisplayRole ) { return model.data( model.index( row, static_cast<int>( column ) ), role ); };
  QCOMPARE( cell( 0, Column::Id ).toString(), QStringLiteral( "left" ) );
  QCOMPARE( cell( 0, Column::Size ).toString(), QStringLiteral( "640 × 480" ) );
  QCOMPARE( cell( 0, Column::F ).toString(), QStringLiteral( "812.400" ) );
  QCOMPARE( cell( 0, Column::F, Qt::EditRole ).toDouble(), 812.4 );
  QCOMPARE( cell( 0, Column::Model ).toString(), QStringLiteral( "opencv" ) );
  QCOMPARE( cell( 0, Column::K1, Qt::EditRole ).toDouble(), -0.21 );
  QCOMPARE( cell( 0, Column::Images ).toInt(), 2 );
  QCOMPARE( cell( 1, Column::Model ).toString(), QStringLiteral( "brown_photo" ) );
  QCOMPARE( cell( 1, Column::P2, Qt::EditRole ).toDouble(), -2.0e-5 );
  QCOMPARE( cell( 1, Column::Images ).toInt(), 1 );
  // no lens model: no coefficients shown, no pixel size given
  QCOMPARE( cell( 2, Column::Model ).toString(), QStringLiteral( "none" ) );
  QVERIFY( cell( 2, Column::K1 ).isNull() );
  QVERIFY( cell( 2, Column::PixelSize ).isNull() );
  QCOMPARE( cell( 2, Column::Images ).toInt(), 0 );
  QVERIFY( !cell( 3, Column::Id ).isValid() );
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
