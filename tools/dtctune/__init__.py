"""dtctune: tune the DTC drive over CANopen from a PC (python-can + canopen)."""

__version__ = "0.1.0"


def need_third_party() -> None:
    """Make the venv's packages (python-can, matplotlib) importable. The `dtctune` launcher that
    tools/setup_venv.sh writes starts Python without the site module (-S: 0.03-0.06 s less
    start-up inside User-Mode Linux, where the short commands need only the standard library);
    the paths site would have added are added here, once, by the commands that need them."""
    import sys
    if sys.flags.no_site and not getattr(sys, "_dtctune_site_done", False):
        import site
        site.main()
        sys._dtctune_site_done = True
