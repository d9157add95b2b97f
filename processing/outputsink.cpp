/***************************************************************************
  outputsink.cpp - how every algorithm writes its tables and counts outcomes
 ***************************************************************************/
#include "outputsink.h"

#include <QStringList>

#include <qgsexception.h>

#include "geostationalgorithm.h"
#include "processingblock.h"

namespace GeoStationProcessing
{

OutputSink::OutputSink( QgsFeatureSink *sink, const QString &destination, const QVariantMap &parameters, const QString &name )
  : mSink( sink ), mDestination( destination ), mParameters( parameters ), mName( name )
{
  if ( !mSink )
    throw QgsProcessingException( GeoStationAlgorithm::invalidSinkError( parameters, name ) );
}

void OutputSink::add( QgsFeature &feature )
{
  requireOpen();
  if ( !mSink->addFeature( feature, QgsFeatureSink::FastInsert ) )
    throw QgsProcessingException( GeoStationAlgorithm::writeFeatureError( mSink.get(), mParameters, mName ) );
}

void OutputSink::add( QgsFeatureList &features )
{
  requireOpen();
  if ( !mSink->addFeatures( features, QgsFeatureSink::FastInsert ) )
    throw QgsProcessingException( GeoStationAlgorithm::writeFeatureError( mSink.get(), mParameters, mName ) );
}

void OutputSink::requireOpen() const
{
  if ( !mSink )
    throw QgsProcessingException( QStringLiteral( "%1 was written to after it was closed: this is a fault of the algorithm, please report it." ).arg( mName ) );
}

QString OutputSink::close( bool nullGeometries )
{
  mSink.reset();
  if ( nullGeometries )
    storeMissingGeometriesAsNull( mDestination );
  return mDestination;
}

QString StatusTally::text() const
{
  QStringList parts;
  for ( auto c = mCounts.constBegin(); c != mCounts.constEnd(); ++c )
    parts << QStringLiteral( "%1 %2" ).arg( c.key() ).arg( c.value() );
  return parts.join( QLatin1String( ", " ) );
}

} // namespace GeoStationProcessing
