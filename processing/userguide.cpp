/***************************************************************************
  userguide.cpp - where the installed user guide is
 ***************************************************************************/
#include "userguide.h"

#include <dlfcn.h>

#include <QDir>
#include <QFileInfo>
#include <QUrl>

namespace GeoStationProcessing
{
  namespace
  {
    //! The folder of the library this function is linked into.
    QString libraryFolder()
    {
      Dl_info info;
      if ( dladdr( reinterpret_cast<const void *>( &libraryFolder ), &info ) == 0 || !info.dli_fname )
        return QString();
      return QFileInfo( QString::fromLocal8Bit( info.dli_fname ) ).absolutePath();
    }
  } // namespace

  QString userGuidePage( const QString &page )
  {
    const QDir library( libraryFolder() );
    for ( const QString &guide : { QStringLiteral( "../share/geostation/docs" ), QStringLiteral( "../docs-html" ) } )
    {
      const QString path = QDir::cleanPath( library.absoluteFilePath( guide + '/' + page ) );
      if ( QFileInfo( path ).isFile() )
        return QUrl::fromLocalFile( path ).toString();
    }
    return QString();
  }
} // namespace GeoStationProcessing
