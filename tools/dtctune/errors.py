"""The one exception type the command line turns into a single error line."""

# Exit statuses of the command line (also listed in `dtctune --help`).
EXIT_OK = 0
EXIT_USAGE = 2      # bad arguments, unknown name, value refused before sending, EDS problems
EXIT_NO_ANSWER = 3  # the drive did not answer (timeout), or the CAN interface is unusable
EXIT_REFUSED = 4    # the drive refused the request (SDO abort)


class DtctuneError(Exception):
    """A failure to report as one line on stderr, with exit status `status`."""

    def __init__(self, message: str, status: int = EXIT_USAGE):
        super().__init__(message)
        self.status = status
