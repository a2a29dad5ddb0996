"""The application: the command line, fault reporting, the at-a-glance table and the
plotting style of the site's figures."""
