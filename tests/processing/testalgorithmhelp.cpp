// Every GeoStation algorithm's help as the Processing dialog shows it: each
// parameter and output named by its label with its name in brackets, and a
// Help button that opens the algorithm's page of the user guide (built as
// HTML into the build folder, installed beside the provider).
#include <QFile>
#include <QRegularExpression>
#include <QUrl>
#include <QtTest/QtTest>

#include <qgsapplication.h>
#include <qgsprocessingalgorithm.h>
#include <qgsprocessingoutputs.h>
#include <qgsprocessingparameters.h>
#include <qgsprocessingprovider.h>
#include <qgsprocessingregistry.h>

#include "geostationprovider.h"
#include "processingtestutils.h"
#include "userguide.h"

class TestAlgorithmHelp : public QObject
{
    Q_OBJECT

  private slots:
    void initTestCase() { QVERIFY( registerGeoStationProvider() ); }
    void parametersAreNamedByTheirLabels();
    void theHelpButtonOpensTheAlgorithmsPage();
    void aPageThatIsNotThereHasNoUrl();
    void theReadableReportsAreHtmlOutputs();

  private:
    static QList<const QgsProcessingAlgorithm *> algorithms()
    {
      return QgsApplication::processingRegistry()->providerById( QStringLiteral( "geostation" ) )->algorithms();
    }
};

void TestAlgorithmHelp::parametersAreNamedByTheirLabels()
{
  QVERIFY( algorithms().size() >= 18 );
  for ( const QgsProcessingAlgorithm *algorithm : algorithms() )
  {
    const QString help = algorithm->shortHelpString();
    QVERIFY2( !help.isEmpty(), qPrintable( algorithm->id() ) );
    QStringList names;
    for ( const QgsProcessingParameterDefinition *p : algorithm->parameterDefinitions() )
      names << p->name();
    for ( const QgsProcessingOutputDefinition *o : algorithm->outputDefinitions() )
      names << o->name();
    for ( const QString &name : names )
    {
      const QString description = algorithm->parameterDefinition( name ) ? algorithm->parameterDefinition( name )->description() : algorithm->outputDefinition( name )->description();
      const QString label = description.left( description.indexOf( QLatin1String( " (" ) ) > 0 ? description.indexOf( QLatin1String( " (" ) ) : description.size() );
      if ( label.compare( name, Qt::CaseInsensitive ) == 0 )
        continue;
      QString unlabelled = help;
      unlabelled.remove( QStringLiteral( "\u201c%1\u201d (%2)" ).arg( label, name ) );
      const int bare = unlabelled.count( QRegularExpression( QStringLiteral( "\\b%1\\b" ).arg( name ) ) );
      QVERIFY2( bare == 0, qPrintable( QStringLiteral( "%1: %2 mentions of %3 without its label" ).arg( algorithm->id() ).arg( bare ).arg( name ) ) );
    }
  }
  // a whole sentence, as extract_roads' help reads in the dialog
  QVERIFY( QgsApplication::processingRegistry()->algorithmById( QStringLiteral( "geostation:extract_roads" ) )->shortHelpString().contains( QStringLiteral( "by at least \u201cMinimum contrast\u201d (MIN_CONTRAST) grey levels" ) ) );
}

void TestAlgorithmHelp::theHelpButtonOpensTheAlgorithmsPage()
{
  for ( const QgsProcessingAlgorithm *algorithm : algorithms() )
  {
    const QUrl url( algorithm->helpUrl() );
    QVERIFY2( url.isLocalFile(), qPrintable( algorithm->id() + QStringLiteral( ": no help page (" ) + algorithm->helpUrl() + ')' ) );
    QFile page( url.toLocalFile() );
    QVERIFY2( page.open( QIODevice::ReadOnly ), qPrintable( url.toLocalFile() ) );
    QVERIFY2( QString::fromUtf8( page.readAll() ).contains( algorithm->id() ), qPrintable( url.toLocalFile() + QStringLiteral( " does not name " ) + algorithm->id() ) );
  }
  QVERIFY( QUrl( GeoStationProcessing::userGuidePage( QStringLiteral( "getting-started.html" ) ) ).isLocalFile() );
}

void TestAlgorithmHelp::theReadableReportsAreHtmlOutputs()
{
  // an HTML output is what QGIS lists in its Results Viewer
  const QStringList expected { "bundle_adjust", "extract_roads", "identify_control", "inner_orientation", "resection" };
  QStringList found;
  for ( const QgsProcessingAlgorithm *algorithm : algorithms() )
    if ( const QgsProcessingOutputDefinition *output = algorithm->outputDefinition( QStringLiteral( "REPORT_HTML" ) ) )
    {
      found << algorithm->name();
      QCOMPARE( output->type(), QgsProcessingOutputHtml::typeName() );
      QVERIFY( algorithm->parameterDefinition( QStringLiteral( "REPORT_HTML" ) )->flags() & QgsProcessingParameterDefinition::FlagOptional );
    }
  found.sort();
  QCOMPARE( found, expected );
}

void TestAlgorithmHelp::aPageThatIsNotThereHasNoUrl()
{
  QCOMPARE( GeoStationProcessing::userGuidePage( QStringLiteral( "algorithms/no_such_algorithm.html" ) ), QString() );
}

int main( int argc, char *argv[] )
{
  return runQgisTests<TestAlgorithmHelp>( argc, argv );
}

#include "testalgorithmhelp.moc"
