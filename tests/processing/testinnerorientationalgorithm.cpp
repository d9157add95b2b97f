// geostation:inner_orientation on a rendered scan: automatic and measured.
#include <QJsonArray>
#include <QJsonDocument>
#include <QJsonObject>
#include <QTemporaryDir>
#include <QtTest/QtTest>

#include <Eigen/Dense>
#include <gdal.h>

#include <qgsapplication.h>
#include <qgsprocessingalgorithm.h>
#include <qgsprocessingcontext.h>
#include <qgsprocessingfeedback.h>
#include <qgsprocessingregistry.h>
#include <qgsproject.h>
#include <qgstest.h>

#include "geometry/rotation.h"
#include "geostationprovider.h"
#include "processingtestutils.h"
#include "io/block.h"

namespace
{
  constexpr int kSize = 2048;
  const double kFiducials[4][2] = { { -95.0, 95.0 }, { 95.0, 95.0 }, { 95.0, -95.0 }, { -95.0, -95.0 } };

  //! A 0.1 mm scan rotated 0.5 degrees with 0.2 % affinity.
  Eigen::Vector2d pixelOf( double xMm, double yMm )
  {
    const double b = geostation::degToRad( 0.5 );
    Eigen::Matrix2d a;
    a << std::cos( b ), std::sin( b ), -std::sin( b ), std::cos( b );
    a = a * Eigen::DiagonalMatrix<double, 2>( 0.1 * 1.002, 0.1 );
    const Eigen::Vector2d uv = Eigen::Vector2d( 1024.0, -1024.0 ) + a.inverse() * Eigen::Vector2d( xMm, yMm );
    return { uv.x(), -uv.y() };
  }

  const char *kBlock = R"json({
    "format": "geostation-block", "version": 1, "crs": "EPSG:32633",
    "cameras": [
      {"id": "rmk", "width": 2048, "height": 2048, "f": 1530.0, "cx": 1024.0, "cy": 1024.0, "pixel_size_mm": 0.1,
       "fiducials": [{"id": "1", "x_mm": -95.0, "y_mm": 95.0}, {"id": "2", "x_mm": 95.0, "y_mm": 95.0},
                     {"id": "3", "x_mm": 95.0, "y_mm": -95.0}, {"id": "4", "x_mm": -95.0, "y_mm": -95.0}]},
      {"id": "digital", "width": 2048, "height": 2048, "f": 1530.0, "cx": 1024.0, "cy": 1024.0}],
    "images": [{"id": "scan17", "camera": "rmk", "path": "scan17.tif"},
               {"id": "gone", "camera": "rmk", "path": "missing.tif"},
               {"id": "dig", "camera": "digital", "path": "scan17.tif"}]})json";
} // namespace

class TestInnerOrientationAlgorithm : public QObject
{
    Q_OBJECT

  private slots:
    void initTestCase();
    void automaticDetectionOrientsTheScan();
    void measuredFiducialsGiveTheSameResult();
    void withoutFiducialsTheMarksAreFoundAutomatically();
    void badInput_data();
    void badInput();

  private:
    QVariantMap run( const QVariantMap &parameters, bool *ok, RecordingFeedback *feedback );
    QString write( const QString &name, const QString &text );
    QTemporaryDir mDir;
    QString mBlock;
    QgsProcessingContext mContext;
};

void TestInnerOrientationAlgorithm::initTestCase()
{
  QVERIFY( registerGeoStationProvider() || QgsApplication::processingRegistry()->providerById( "geostation" ) );
  mBlock = write( "film.geostation.json", QString::fromLatin1( kBlock ) );
  // Dark film base with bright 20 px discs, 8x8 supersampled.
  std::vector<unsigned char> pixels( static_cast<size_t>( kSize ) * kSize, 40 );
  for ( const auto &f : kFiducials )
  {
    const Eigen::Vector2d c = pixelOf( f[0], f[1] );
    for ( int y = static_cast<int>( c.y() ) - 14; y <= static_cast<int>( c.y() ) + 14; ++y )
      for ( int x = static_cast<int>( c.x() ) - 14; x <= static_cast<int>( c.x() ) + 14; ++x )
      {
        double cover = 0.0;
        for ( int sy = 0; sy < 8; ++sy )
          for ( int sx = 0; sx < 8; ++sx )
            cover += std::hypot( x + ( sx + 0.5 ) / 8 - c.x(), y + ( sy + 0.5 ) / 8 - c.y() ) <= 10.0 ? 1.0 / 64 : 0.0;
        pixels[static_cast<size_t>( y ) * kSize + x] = static_cast<unsigned char>( std::lround( 40 + 180 * cover ) );
      }
  }
  GDALAllRegister();
  GDALDatasetH ds = GDALCreate( GDALGetDriverByName( "GTiff" ), mDir.filePath( "scan17.tif" ).toUtf8().constData(), kSize, kSize, 1, GDT_Byte, nullptr );
  QCOMPARE( GDALRasterIO( GDALGetRasterBand( ds, 1 ), GF_Write, 0, 0, kSize, kSize, pixels.data(), kSize, kSize, GDT_Byte, 0, 0 ), CE_None );
  GDALClose( ds );
  mContext.setProject( QgsProject::instance() );
}

QString TestInnerOrientationAlgorithm::write( const QString &name, const QString &text )
{
  QFile file( mDir.filePath( name ) );
  file.open( QIODevice::WriteOnly );
  file.write( text.toUtf8() );
  return file.fileName();
}

QVariantMap TestInnerOrientationAlgorithm::run( const QVariantMap &parameters, bool *ok, RecordingFeedback *feedback )
{
  std::unique_ptr<QgsProcessingAlgorithm> alg( QgsApplication::processingRegistry()->algorithmById( "geostation:inner_orientation" )->create() );
  return alg->run( parameters, mContext, feedback, ok );
}

void TestInnerOrientationAlgorithm::automaticDetectionOrientsTheScan()
{
  bool ok = false;
  RecordingFeedback feedback;
  const QString outBlock = mDir.filePath( "auto.geostation.json" ), report = mDir.filePath( "auto.json" );
  const QString html = mDir.filePath( "auto.html" );
  const QVariantMap result = run( { { "BLOCK", mBlock }, { "IMAGE", "scan17" }, { "AUTO", true }, { "MARK_DIAMETER_PX", 20.0 },
    { "OUTPUT_BLOCK", outBlock }, { "REPORT", report }, { "REPORT_HTML", html } }, &ok, &feedback );
  QVERIFY2( ok, qPrintable( feedback.errors.join( '\n' ) ) );
  QGSCOMPARENEAR( result.value( "AFFINITY_PCT" ).toDouble(), 0.2, 0.005 );

  QFile file( report );
  QVERIFY( file.open( QIODevice::ReadOnly ) );
  const QJsonObject json = QJsonDocument::fromJson( file.readAll() ).object();
  QGSCOMPARENEAR( json.value( "beta" ).toDouble(), 0.5, 0.002 );
  QGSCOMPARENEAR( json.value( "A" ).toDouble(), 0.1002, 1e-5 );
  QGSCOMPARENEAR( json.value( "B" ).toDouble(), 0.1, 1e-5 );
  QCOMPARE( json.value( "method" ).toString(), QStringLiteral( "auto" ) );
  QCOMPARE( json.value( "detections" ).toArray().size(), 4 );
  QCOMPARE( json.value( "residuals" ).toArray().size(), 4 );

  // the page: the affinity as the JSON has it, a row and a point per fiducial
  const HtmlReportShape page = readHtmlReport( html );
  QVERIFY2( page.error.isEmpty(), qPrintable( page.error ) );
  QCOMPARE( page.row( QStringLiteral( "affinity (%)" ) ).value( 1 ), QString::number( json.value( "affinity_pct" ).toDouble(), 'f', 4 ) );
  for ( const QJsonValue &r : json.value( "residuals" ).toArray() )
  {
    const QStringList row = page.row( r.toObject().value( "fiducial_id" ).toString() );
    QCOMPARE( row.size(), 6 );
    QGSCOMPARENEAR( row.at( 1 ).toDouble(), 1000.0 * r.toObject().value( "dx_mm" ).toDouble(), 0.01 );
  }
  QCOMPARE( page.points, 4 );
  QCOMPARE( page.histogramCount, 4 );

  const geostation::Block block = geostation::Block::load( outBlock.toStdString() );
  const geostation::BlockImage &image = block.image( "scan17" );
  QVERIFY( image.innerOrientation.has_value() );
  // The mark of fiducial 2 maps back to its calibrated position.
  const Eigen::Vector2d p = pixelOf( 95.0, 95.0 );
  const Eigen::Vector2d mm = image.innerOrientation->photoFromPixel.leftCols<2>() * p + image.innerOrientation->photoFromPixel.col( 2 );
  QGSCOMPARENEAR( mm.x(), 95.0, 0.005 );
  QGSCOMPARENEAR( mm.y(), 95.0, 0.005 );
}

void TestInnerOrientationAlgorithm::measuredFiducialsGiveTheSameResult()
{
  QString csv = QStringLiteral( "image_id,fiducial_id,col,row\nother,1,5,5\n" );
  for ( int k = 0; k < 4; ++k )
  {
    const Eigen::Vector2d p = pixelOf( kFiducials[k][0], kFiducials[k][1] );
    csv += QStringLiteral( "scan17,%1,%2,%3\n" ).arg( k + 1 ).arg( p.x(), 0, 'f', 6 ).arg( p.y(), 0, 'f', 6 );
  }
  bool ok = false;
  RecordingFeedback feedback;
  const QString report = mDir.filePath( "measured.json" );
  run( { { "BLOCK", mBlock }, { "IMAGE", "scan17" }, { "FIDUCIALS", write( "fiducials.csv", csv ) },
    { "OUTPUT_BLOCK", mDir.filePath( "measured.geostation.json" ) }, { "REPORT", report } }, &ok, &feedback );
  QVERIFY2( ok, qPrintable( feedback.errors.join( '\n' ) ) );
  QFile file( report );
  QVERIFY( file.open( QIODevice::ReadOnly ) );
  const QJsonObject json = QJsonDocument::fromJson( file.readAll() ).object();
  QGSCOMPARENEAR( json.value( "beta" ).toDouble(), 0.5, 1e-6 );
  QGSCOMPARENEAR( json.value( "affinity_pct" ).toDouble(), 0.2, 1e-5 );
  QGSCOMPARENEAR( json.value( "alpha_A" ).toDouble(), 0.0, 1e-4 );
  QGSCOMPARENEAR( json.value( "rms_residual_mm" ).toDouble(), 0.0, 1e-6 );
}

void TestInnerOrientationAlgorithm::withoutFiducialsTheMarksAreFoundAutomatically()
{
  // the block and the image alone, as a user runs it first: no FIDUCIALS, so they are found (the defaults' mark size)
  bool ok = false;
  RecordingFeedback feedback;
  const QString outBlock = mDir.filePath( "minimal.geostation.json" );
  const QVariantMap result = run( { { "BLOCK", mBlock }, { "IMAGE", "scan17" }, { "OUTPUT_BLOCK", outBlock } }, &ok, &feedback );
  QVERIFY2( ok, qPrintable( feedback.errors.join( '\n' ) ) );
  QGSCOMPARENEAR( result.value( "AFFINITY_PCT" ).toDouble(), 0.2, 0.005 );
  QVERIFY( geostation::Block::load( outBlock.toStdString() ).image( "scan17" ).innerOrientation.has_value() );
}

void TestInnerOrientationAlgorithm::badInput_data()
{
  QTest::addColumn<QString>( "image" );
  QTest::addColumn<bool>( "automatic" );
  QTest::addColumn<QString>( "fiducials" );
  QTest::addColumn<QString>( "expected" );
  QTest::newRow( "camera without fiducials" ) << "dig" << true << QString() << "defines 0 fiducials";
  QTest::newRow( "missing scan" ) << "gone" << true << QString() << "does not exist";
  QTest::newRow( "two fiducials" ) << "scan17" << false << "fiducial_id,col,row\n1,74,74\n2,1974,74\n" << "at least three";
  QTest::newRow( "unknown fiducial" ) << "scan17" << false << "fiducial_id,col,row\n1,74,74\n2,1974,74\n9,1974,1974\n" << "does not define it";
}

void TestInnerOrientationAlgorithm::badInput()
{
  QFETCH( QString, image );
  QFETCH( bool, automatic );
  QFETCH( QString, fiducials );
  QFETCH( QString, expected );
  const QString tag = QString( QTest::currentDataTag() ).replace( ' ', '-' );
  QVariantMap parameters { { "BLOCK", mBlock }, { "IMAGE", image }, { "AUTO", automatic },
    { "OUTPUT_BLOCK", mDir.filePath( "never.geostation.json" ) }, { "REPORT", mDir.filePath( "never.json" ) } };
  if ( !fiducials.isEmpty() )
    parameters.insert( "FIDUCIALS", write( QStringLiteral( "fid-%1.csv" ).arg( tag ), fiducials ) );
  bool ok = true;
  RecordingFeedback feedback;
  run( parameters, &ok, &feedback );
  QVERIFY( !ok );
  QVERIFY2( feedback.errors.join( ' ' ).contains( expected ), qPrintable( feedback.errors.join( '\n' ) ) );
  QVERIFY( !QFile::exists( mDir.filePath( "never.geostation.json" ) ) );
  QVERIFY( !QFile::exists( mDir.filePath( "never.json" ) ) );
}

int main( int argc, char **argv )
{
  return runQgisTests<TestInnerOrientationAlgorithm>( argc, argv );
}

#include "testinnerorientationalgorithm.moc"
