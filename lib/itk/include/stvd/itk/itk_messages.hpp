// Where ITK's own messages go while stvd reads and writes images.
//
// stvd's ITK file I/O changes nothing a host process owns: it never replaces
// ITK's output window and never touches file descriptor 2 or std::cerr. Every
// problem it finds is thrown as an stvd::imaging::ImageIoError whose message
// carries what ITK's exception said, and what a header looks like (an
// Analyze 7.5 file, for instance) is reported in stvd's own words. ITK's
// warnings during a call (the three-line "WARNING: In .../itkNiftiImageIO.cxx
// ..." text) go where the host has sent ITK's output, as for any ITK call of
// its own; niftilib prints some failures with fprintf(stderr), which stvd
// detects without reading standard error (every written file is checked).
//
// A program that owns its process and wants one line of its own per problem
// (the `stvd` tool) installs stvd's output window once, at start-up, before
// any thread reads an image.
#pragma once

namespace stvd::imaging {

/// Installs, for the whole process, an ITK output window that keeps ITK's
/// messages given on a thread inside one of stvd's ITK calls off the
/// terminal (they are dropped), and hands every other message to the window
/// that was installed before, unchanged. Call it once, early, from the
/// program that owns the process (a library or plug-in should not: it would
/// take ITK's messages from its host). Calling it again does nothing.
/// Installing another window afterwards (itk::OutputWindow::SetInstance)
/// takes precedence.
void installItkMessageFilter();

}  // namespace stvd::imaging
