"""A plugin as a user would write one (tests/test_plugins.py installs it): an
optimizer, a behaviour with an option of its own and a scene, each in a
module of its own, named by entry points in its distribution's metadata."""
