"""Runs python-msp430-tools' `msp430-bsl` unchanged on a pseudo-terminal.

A pseudo-terminal lacks two things of a serial port that `msp430-bsl` asks for:

* modem lines: `msp430-bsl` drives the MSP430's RST and TEST pins through DTR and RTS
  (the BSL entry sequence, and a level set on both even with --no-start), and
  pyserial's setters fail on a pty with ENOTTY ("Inappropriate ioctl for device");
* parity: the BSL's line is 8E1 (msp430-bsl asks for 8E2), and this machine's kernel
  refuses PARENB on a pty with EINVAL.

This wrapper turns exactly those failures, on a pty only, into "not there" (the modem
line setters do nothing; the port is configured again without parity) and then runs
`msp430-bsl` with the arguments given. Any other error, and everything on a real
serial port, behaves as before.

What it means for the test: the entry sequence is not exercised (run `msp430-bsl`
with --no-start; `fpgfx-sim --bootloader msp430` starts in the BSL), and parity
never reaches a wire. Every byte of the protocol is `msp430-bsl`'s own. See
docs/flash.md.
"""

import errno
import os
import sys
import termios

import serial
import serial.serialposix as posix


def _is_pty(fd):
    try:
        return os.ttyname(fd).startswith("/dev/pts/")
    except OSError:
        return False


def _tolerate_missing_modem_lines(setter):
    def wrapped(self, *args, **kwargs):
        try:
            return setter(self, *args, **kwargs)
        except OSError as e:
            if e.errno != errno.ENOTTY:
                raise
            return None

    return wrapped


def _without_parity_on_a_pty(reconfigure):
    def wrapped(self, *args, **kwargs):
        try:
            return reconfigure(self, *args, **kwargs)
        except termios.error as e:
            if e.args[0] != errno.EINVAL or self._parity == serial.PARITY_NONE:
                raise
            if not _is_pty(self.fd):
                raise
            parity = self._parity
            self._parity = serial.PARITY_NONE
            try:
                return reconfigure(self, *args, **kwargs)
            finally:
                self._parity = parity

    return wrapped


for _name in ("_update_dtr_state", "_update_rts_state"):
    setattr(posix.Serial, _name, _tolerate_missing_modem_lines(getattr(posix.Serial, _name)))
posix.Serial._reconfigure_port = _without_parity_on_a_pty(posix.Serial._reconfigure_port)

from msp430.bsl.target import SerialBSLTarget  # noqa: E402  (after the patches)

# What `msp430-bsl` runs (msp430.bsl.target.main), keeping hold of the target so that
# the --output file is closed here: msp430-bsl leaves that to the interpreter's exit,
# which does not reliably flush it (the upload then arrives empty).
sys.argv[0] = "msp430-bsl"
target = SerialBSLTarget()
try:
    target.main()
finally:
    output = getattr(target, "output", None)
    if output is not None and output is not sys.stdout:
        output.close()
