//! flexmb command-line layer
