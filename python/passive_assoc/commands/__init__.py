"""The commands that run a method on the user's own files: ``passive-assoc initiate``,
``associate``, ``locate``, ``associate-tracks`` and ``track``. Methods that gain a file
command follow the same pattern: a module with ``add_arguments(parser)`` and ``main(args)``, inputs read by
:func:`.common.read_inputs`, the method's parameters from its declared constraints, and
outputs written with :func:`.common.write_atomically`."""
