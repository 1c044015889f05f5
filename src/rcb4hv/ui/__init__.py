"""``rcb4hv ui``: a browser dashboard (NiceGUI) for a real board or the emulator.

Pages: Board, Servos, Remote, Motions, Project, Teach (one module each). Every command goes
through one :class:`~rcb4hv.session.BoardSession`; :mod:`rcb4hv.ui.security` guards the
server. Needs the ``ui`` extra: ``pip install 'rcb4hv[ui]'``.
"""
