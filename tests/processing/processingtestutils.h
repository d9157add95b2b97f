// Shared by the provider tests: a feedback that records messages, and the
// main() that runs a QtTest object inside an initialised QgsApplication.
#ifndef GEOSTATION_PROCESSINGTESTUTILS_H
#define GEOSTATION_PROCESSINGTESTUTILS_H

#include <QStringList>
#include <QtTest/QtTest>

#include <qgsapplication.h>
#include <qgsprocessingfeedback.h>

#include "simulation/surveysimulator.h"

//! Collects what an algorithm reports, so tests can read its messages.
class RecordingFeedback : public QgsProcessingFeedback
{
  public:
    void reportError( const QString &error, bool fatal = false ) override
    {
      errors << error;
      QgsProcessingFeedback::reportError( error, fatal );
    }
    void pushWarning( const QString &warning ) override
    {
      warnings << warning;
      QgsProcessingFeedback::pushWarning( warning );
    }
    void pushInfo( const QString &info ) override
    {
      infos << info;
      QgsProcessingFeedback::pushInfo( info );
    }
    QStringList errors, warnings, infos;
};

//! The aerial_stereo preset's pair of 2 stations at 0.5 m (seed 3, noise 4) simulated into `dir`: what the road tests run on.
inline void simulateAerialRoadPair( const QString &dir )
{
  geostation::SimulationOptions options;
  options.preset = geostation::SurveyPreset::AerialStereo;
  options.outputDir = dir.toStdString();
  options.stations = 2;
  options.groundPixelSizeM = 0.5;
  options.seed = 3;
  options.degradation.noiseSigma = 4.0;
  geostation::simulateSurvey( options );
}

//! Runs the tests of T with QGIS initialised (no GUI).
template <typename T>
int runQgisTests( int argc, char **argv )
{
  QgsApplication app( argc, argv, false );
  QgsApplication::init();
  QgsApplication::initQgis();
  int result = 0;
  {
    // Destroyed before exitQgis(): it holds layers whose providers must still exist.
    T test;
    result = QTest::qExec( &test, argc, argv );
  }
  QgsApplication::exitQgis();
  return result;
}

#endif
