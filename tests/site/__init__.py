"""Tests of the site, the examples, the install and the layout of the repository."""
