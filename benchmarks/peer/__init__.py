"""Peer comparison with OpenSees (OpenSeesPy): the same model, built from one seispound description."""
