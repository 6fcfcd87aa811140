"""Byte patches to pythonfmu 0.7.0's Linux binary (``libpythonfmu-export.so``), made by the build.

pythonfmu's C++ layer decides every FMI status the Python slave can give (pythonfmu
``src/pythonfmu/PySlaveInstance.cpp`` and ``fmi2.cpp`` at 0.7.0):

* ``do_step`` returning False gives fmi2Discard and sets the component's ``wantsToTerminate``,
  which nothing ever clears (fmi2GetBooleanStatus(fmi2Terminated) stays true);
* any Python exception goes through ``handle_py_exception``: it releases the Python class,
  instance and log queue (``Py_XDECREF``, pointers kept), then throws ``fatal_error``, which
  every fmi2 function maps to fmi2Fatal. The next call on that instance uses a freed object;
* every other return value (``exit_initialization_mode``, setters) is dropped: fmi2OK.

So fmi2Error, the status FMI 2.0 gives a refused call, cannot be had from Python at all. The
patches below make a Python exception an fmi2Error that leaves the instance intact, and make a
discarded step fmi2Discard without fmi2Terminated: the slave discards a step only for a state it
refuses (a non-finite input, the wall, a state too far outside a surrogate's domain), and a retry
with another state can succeed; where the slave cannot serve a call it raises (fmi2Error, the
instance intact), so nothing is left that would need fmi2Terminated. Each one is located through the ELF
symbol and relocation tables and verified byte for byte (original or already patched) before
anything is written; if one does not match (another pythonfmu build), none of the status
patches is applied and the slave keeps pythonfmu's statuses (``STATUS_PATCHES``).

=================  =======================================================================
name               what it changes
=================  =======================================================================
exit-unload        ``onLibraryUnload`` -> ``ret``: the interpreter state was released twice
                   at process exit (heap corruption, abort in about half the runs)
keep-instance      ``handle_py_exception`` skips its three ``Py_XDECREF``: the Python
                   instance survives an exception and the next call works (also on the
                   path taken after a getString, which entered them from the side: each
                   such error released the class once, until an instantiation failed)
error-status       the exception is thrown with the type ``std::runtime_error`` instead of
                   ``fatal_error``: fmi2.cpp's ``catch (std::exception&)`` returns fmi2Error
error-message      its log line reads "fmi2Error from the Python slave [doStep] ... <repr>"
                   on one line (was "Fatal py exception encountered: [doStep] ...\\n<repr>")
step-terminated    fmi2DoStep: a discarded step leaves ``wantsToTerminate`` false (was: set,
                   and never cleared), a successful step clears it
restore-terminated fmi2SetFMUstate: a successful restore clears ``wantsToTerminate``
free-once          fmi2FreeInstance frees the logger and the slave (the Python instance with
                   it) and sets their pointers to null, but keeps the 32-byte component: a
                   second fmi2FreeInstance of it finds nothing to free (was: a double free,
                   the host aborts). Any other call after the free still dereferences the
                   null slave (a crash): pythonfmu's C++ layer has no check to hang that on
=================  =======================================================================
"""

from __future__ import annotations

import re
import struct
from dataclasses import dataclass

STATUS_PATCHES = ("keep-instance", "error-status", "error-message", "step-terminated", "restore-terminated")

_SHT_SYMTAB, _SHT_RELA, _SHT_DYNSYM, _SHT_NOBITS = 2, 4, 11, 8
_R_X86_64_64, _R_X86_64_GLOB_DAT = 1, 6


class PatchMismatch(Exception):
    """The binary's code is not the code a patch was written for."""


@dataclass(frozen=True)
class _Symbol:
    name: str
    value: int  # virtual address
    size: int


class _Elf:
    """The few parts of a 64-bit little-endian ELF shared library the patches need."""

    def __init__(self, data: bytes):
        if data[:4] != b"\x7fELF" or data[4] != 2 or data[5] != 1:
            raise PatchMismatch("not a 64-bit little-endian ELF file")
        shoff, = struct.unpack_from("<Q", data, 0x28)
        shentsize, shnum = struct.unpack_from("<HH", data, 0x3A)
        self.sections = [struct.unpack_from("<IIQQQQIIQQ", data, shoff + i * shentsize) for i in range(shnum)]
        self.symbols: dict[str, _Symbol] = {}
        self.relocations: list[tuple[int, int, str]] = []  # (address, type, symbol name)
        for sh in self.sections:
            if sh[1] in (_SHT_SYMTAB, _SHT_DYNSYM):
                for name, value, size in self._symbol_table(data, sh):
                    if value and name not in self.symbols:
                        self.symbols[name] = _Symbol(name, value, size)
            elif sh[1] == _SHT_RELA:
                names = [n for n, _v, _s in self._symbol_table(data, self.sections[sh[6]])]
                for k in range(sh[5] // 24):
                    address, info, _addend = struct.unpack_from("<QQq", data, sh[4] + 24 * k)
                    sym = info >> 32
                    self.relocations.append((address, info & 0xFFFFFFFF, names[sym] if sym < len(names) else ""))

    def _symbol_table(self, data: bytes, sh):
        strtab = self.sections[sh[6]]
        for k in range(sh[5] // sh[9]):
            name_off, _info, _other, _shndx, value, size = struct.unpack_from("<IBBHQQ", data, sh[4] + k * sh[9])
            start = strtab[4] + name_off
            name = data[start:data.index(b"\0", start)].decode("ascii", "replace")
            yield name, value, size

    def offset(self, address: int) -> int:
        """File offset of a virtual address."""
        for sh in self.sections:
            if sh[1] != _SHT_NOBITS and sh[3] and sh[3] <= address < sh[3] + sh[5]:
                return address - sh[3] + sh[4]
        raise PatchMismatch(f"address {address:#x} is in no section")

    def symbol(self, name: str) -> _Symbol:
        if name not in self.symbols:
            raise PatchMismatch(f"symbol {name} not found")
        return self.symbols[name]

    def relocation(self, kind: int, symbol: str) -> list[int]:
        """Addresses of the relocations of ``kind`` against ``symbol``."""
        return [a for a, t, s in self.relocations if t == kind and s.split("@")[0] == symbol]


# A patch: (name, locate) where locate(elf, data) returns [(file offset, original, patched)]
# after verifying the code around them; it raises PatchMismatch when the code differs.

def _exit_unload(elf: _Elf, data: bytes):
    # (anonymous namespace)::onLibraryUnload(): endbr64; jmp finalizePythonInterpreter
    off = elf.offset(elf.symbol("_ZN12_GLOBAL__N_115onLibraryUnloadEv").value)
    return [(off + 4, b"\xe9", b"\xc3")]


_HANDLE = "_ZNK15PySlaveInstance19handle_py_exceptionERKNSt7__cxx1112basic_stringIcSt11char_traitsIcESaIcEEE16PyGILState_STATE"


def _function(elf: _Elf, data: bytes, name: str) -> tuple[int, int, bytes]:
    """(address, file offset, code) of a function."""
    sym = elf.symbol(name)
    off = elf.offset(sym.value)
    return sym.value, off, data[off:off + sym.size]


# After clearing a non-empty string buffer (a getString earlier in this instance's life), the
# code enters the three Py_XDECREF from the side, past the first instruction: at the loop's end
#   mov rdi, [r13 + 0x68]; mov [r13 + 0x88], rax; test rdi, rdi; jne <1st XDECREF + 9>; jmp <2nd>
# (25 bytes). That path becomes: mov [r13 + 0x88], rax (the buffer's clear); jmp over all three.
_AFTER_STRINGS = re.compile(rb"\x49\x8b\x7d\x68\x49\x89\x85\x88\x00\x00\x00\x48\x85\xff\x0f\x85(....)\xe9(....)",
                            re.S)
_NOPS_13 = bytes.fromhex("0f1f440000" "0f1f440000" "0f1f00")


def _keep_instance(elf: _Elf, data: bytes):
    # cleanPyObject's Py_XDECREF(pClass_), (pInstance_), (pMessages_): members at 0x68, 0x70,
    # 0x78 of PySlaveInstance (r13 = this), each 26 bytes; jump over all three (0x4c + 2 = 78),
    # on the straight path and on the one after clearing the string buffer (_AFTER_STRINGS)
    addr, off, code = _function(elf, data, _HANDLE)
    one = rb"\x48\x85\xff\x74\x11\x8b\x07\x85\xc0\x78\x0b\x83\xe8\x01\x89\x07\x0f\x84...."
    pat = re.compile(rb"(?:\x49\x8b|\xeb\x4c)\x7d\x68" + one + rb"\x49\x8b\x7d\x70" + one + rb"\x49\x8b\x7d\x78" + one,
                     re.S)
    hits = list(pat.finditer(code))
    if len(hits) != 1:
        raise PatchMismatch(f"handle_py_exception: {len(hits)} matches of the three Py_XDECREF")
    block = addr + hits[0].start()
    side = []
    for m in _AFTER_STRINGS.finditer(code):
        at = addr + m.start()
        jne = at + 20 + struct.unpack("<i", m.group(1))[0]
        jmp = at + 25 + struct.unpack("<i", m.group(2))[0]
        if (jne, jmp) == (block + 9, block + 26):
            side.append(m)
    done = [m for m in re.finditer(rb"\x49\x89\x85\x88\x00\x00\x00\xe9(....)" + re.escape(_NOPS_13), code, re.S)
            if addr + m.start() + 12 + struct.unpack("<i", m.group(1))[0] == block + 78]
    if len(side) + len(done) != 1:
        raise PatchMismatch(f"handle_py_exception: {len(side) + len(done)} side entries into the three Py_XDECREF")
    at = (side or done)[0].start()
    jump = b"\x49\x89\x85\x88\x00\x00\x00\xe9" + struct.pack("<i", block + 78 - (addr + at + 12)) + _NOPS_13
    return [(off + hits[0].start(), b"\x49\x8b", b"\xeb\x4c"),
            (off + at, side[0].group(0) if side else jump, jump)]


def _error_status(elf: _Elf, data: bytes):
    # throw fatal_error(...): mov rsi, [rip + GOT(typeinfo fatal_error)]; mov rdi, r13; call __cxa_throw
    # -> mov rsi, [rip + typeinfo(fatal_error) + 16], its base-class pointer = &typeinfo(runtime_error)
    addr, off, code = _function(elf, data, _HANDLE)
    ti = elf.symbol("_ZTIN9pythonfmu11fatal_errorE").value
    base = ti + 16
    if base not in elf.relocation(_R_X86_64_64, "_ZTISt13runtime_error"):
        raise PatchMismatch("typeinfo of fatal_error does not name std::runtime_error as its base")
    got = set(elf.relocation(_R_X86_64_GLOB_DAT, "_ZTIN9pythonfmu11fatal_errorE"))
    found = []
    for m in re.finditer(rb"\x48\x8b\x35(....)\x4c\x89\xef\xe8", code, re.S):
        insn = addr + m.start()
        target = insn + 7 + struct.unpack("<i", m.group(1))[0]
        if target in got or target == base:
            new = struct.pack("<i", base - (insn + 7))
            found.append((off + m.start() + 3, m.group(1) if target in got else None, new))
    if len(found) != 1:
        raise PatchMismatch(f"handle_py_exception: {len(found)} throws of fatal_error")
    at, old, new = found[0]
    return [(at, old if old is not None else new, new)]


_PREFIX, _NEW_PREFIX = b"Fatal py exception encountered: ", b"fmi2Error from the Python slave "


def _error_message(elf: _Elf, data: bytes):
    # the log line's prefix (same length), and its "\n" before the exception's repr -> the
    # prefix's last byte, a space: one line
    addr, off, code = _function(elf, data, _HANDLE)
    text = [data.find(p) for p in (_PREFIX, _NEW_PREFIX)]
    at = max(text)
    if min(text) != -1 or at < 0 or data.count(data[at:at + 32]) != 1:
        raise PatchMismatch("the 'Fatal py exception encountered' text is not there once")
    prefix_addr = next(sh[3] + at - sh[4] for sh in elf.sections
                       if sh[1] != _SHT_NOBITS and sh[3] and sh[4] <= at < sh[4] + sh[5])
    space = prefix_addr + len(_PREFIX) - 1
    # mov edx, 1; lea rsi, [rip + "\n"]; call __ostream_insert
    hits = list(re.finditer(rb"\xba\x01\x00\x00\x00\x48\x8d\x35(....)\xe8", code, re.S))
    if len(hits) != 1:
        raise PatchMismatch(f"handle_py_exception: {len(hits)} one-character inserts")
    m = hits[0]
    insn = addr + m.start() + 5
    target = insn + 7 + struct.unpack("<i", m.group(1))[0]
    new = struct.pack("<i", space - (insn + 7))
    if target != space and data[elf.offset(target):elf.offset(target) + 1] != b"\n":
        raise PatchMismatch("handle_py_exception: the one-character insert is not a newline")
    old = m.group(1) if target != space else new
    return [(at, _PREFIX if text[0] >= 0 else _NEW_PREFIX, _NEW_PREFIX),
            (off + m.start() + 8, old, new)]


# fmi2DoStep from the test of Step()'s result to the call of __stack_chk_fail (71 bytes)
_DOSTEP = bytes.fromhex(
    "84c0" "7530"                          # test al, al; jne ok
    "f20f101424" "c6430801" "b802000000" "f20f1113"  # discard: terminated = 1, status 2
    "488b542438" "64482b142528000000" "7521"  # epilogue: stack check
    "4883c440" "5b" "5d" "415c" "c3"
    "0f1f440000"                           # padding
    "f20f100424" "f20f58442408" "31c0" "f20f1103" "ebcf")  # ok: lastSuccessfulTime = t + h, status 0
# the ok path, moved into the padding, also stores al = 0 into terminated; the discard path stores
# 0 instead of 1 (the same instruction, its immediate byte): Discard without Terminated
_DISCARD_AT = _DOSTEP.index(bytes.fromhex("c6430801")) + 3
_DOSTEP_CLEARS = (_DOSTEP[:2] + b"\x75\x2b" + _DOSTEP[4:47] + bytes.fromhex(
    "f20f100424" "f20f58442408" "31c0" "884308" "f20f1103" "ebd1" "6690"))  # + terminated = al = 0
_DOSTEP_NEW = _DOSTEP_CLEARS[:_DISCARD_AT] + b"\x00" + _DOSTEP_CLEARS[_DISCARD_AT + 1:]


def _step_terminated(elf: _Elf, data: bytes):
    _addr, off, code = _function(elf, data, "fmi2DoStep")
    for body in (_DOSTEP, _DOSTEP_CLEARS, _DOSTEP_NEW):  # pythonfmu's; this patch's earlier version; this one
        at = code.find(body)
        if at >= 0 and code.find(body, at + 1) < 0:
            return [(off + at, body if body != _DOSTEP_NEW else _DOSTEP, _DOSTEP_NEW)]
    raise PatchMismatch("fmi2DoStep has unexpected code")


# fmi2SetFMUstate after the call of SetFMUstate(): status 0, stack check, epilogue, the call
# of __stack_chk_fail (32 bytes); the patch stores al = 0 into terminated and, for room,
# jumps to the next function's identical call of __stack_chk_fail (it never returns)
_RESTORE = re.compile(rb"\x31\xc0\x48\x8b\x54\x24\x38\x64\x48\x2b\x14\x25\x28\x00\x00\x00\x75\x09"
                      rb"\x48\x83\xc4\x40\x5b\x5d\x41\x5c\xc3\xe8(....)", re.S)
_RESTORE_NEW = re.compile(rb"\x31\xc0\x88\x43\x08\x48\x8b\x54\x24\x38\x64\x48\x2b\x14\x25\x28\x00\x00\x00"
                          rb"\x75(.)\x48\x83\xc4\x40\x5b\x5d\x41\x5c\xc3\x66\x90", re.S)
_EPILOGUE_CALL = re.compile(rb"\x75\x09\x48\x83\xc4.\x5b\x5d\x41\x5c\xc3\xe8(....)", re.S)


def _restore_terminated(elf: _Elf, data: bytes):
    addr, off, code = _function(elf, data, "fmi2SetFMUstate")
    if not code.startswith(bytes.fromhex("f30f1efa4154555348 89fb".replace(" ", ""))):  # rbx = component
        raise PatchMismatch("fmi2SetFMUstate does not keep the component in rbx")
    m = _RESTORE.search(code)
    if m is None:
        m2 = _RESTORE_NEW.search(code)
        if m2 is None:
            raise PatchMismatch("fmi2SetFMUstate has unexpected code")
        return [(off + m2.start(), m2.group(0), m2.group(0))]
    call_at = addr + m.start() + 27
    chk = call_at + 5 + struct.unpack("<i", m.group(1))[0]  # __stack_chk_fail@plt
    jne_end = addr + m.start() + 21
    nxt = elf.symbol("fmi2FreeFMUstate")
    n_off = elf.offset(nxt.value)
    for e in _EPILOGUE_CALL.finditer(data[n_off:n_off + nxt.size]):
        other = nxt.value + e.start() + 11
        if other + 5 + struct.unpack("<i", e.group(1))[0] == chk and -128 <= other - jne_end <= 127:
            new = (b"\x31\xc0\x88\x43\x08" + m.group(0)[2:16] + b"\x75" + struct.pack("<b", other - jne_end)
                   + m.group(0)[18:27] + b"\x66\x90")
            return [(off + m.start(), m.group(0), new)]
    raise PatchMismatch("no call of __stack_chk_fail within reach in fmi2FreeFMUstate")


# fmi2FreeInstance after the slave's deletion (``delete slave`` through its vtable): the epilogue
# that deletes the component (``jmp operator delete(component, 0x20)``), 23 bytes, becomes one
# that sets component->slave and ->logger (+0x10, +0x18; r12 = component) to null and returns
_FREE_DELETE_SLAVE = re.compile(rb"\x49\x8b\x7c\x24\x10\x48\x85\xff\x74\x09\x48\x8b\x07\xff\x90\xa8\x00\x00\x00")
_FREE_EPILOGUE = re.compile(rb"\x48\x83\xc4\x08\x4c\x89\xe7\xbe\x20\x00\x00\x00"  # add rsp, 8; rdi = r12; esi = 0x20
                            rb"\x5b\x5d\x41\x5c\x41\x5d\xe9(....)", re.S)  # pop rbx, rbp, r12, r13; jmp delete
_FREE_EPILOGUE_NEW = bytes.fromhex("4883c408" "31c0" "4989442410" "4989442418" "5b5d415c415d" "c3")


def _free_once(elf: _Elf, data: bytes):
    addr, off, code = _function(elf, data, "fmi2FreeInstance")
    slave = list(_FREE_DELETE_SLAVE.finditer(code))
    if len(slave) != 1:
        raise PatchMismatch(f"fmi2FreeInstance: {len(slave)} deletions of the slave")
    at = slave[0].end()
    if code[at:at + len(_FREE_EPILOGUE_NEW)] == _FREE_EPILOGUE_NEW:
        return [(off + at, _FREE_EPILOGUE_NEW, _FREE_EPILOGUE_NEW)]
    m = _FREE_EPILOGUE.match(code, at)
    if m is None:
        raise PatchMismatch("fmi2FreeInstance: no deletion of the component after the slave's")
    # the jmp goes where the function's calls of operator delete go (call rel32 before the slave's deletion)
    target = addr + m.end() + struct.unpack("<i", m.group(1))[0]
    calls = {addr + c.end() + struct.unpack("<i", c.group(1))[0] for c in re.finditer(rb"\xe8(....)", code[:at], re.S)}
    if target not in calls:
        raise PatchMismatch("fmi2FreeInstance: the last jump is not to the operator delete the function calls")
    return [(off + at, m.group(0), _FREE_EPILOGUE_NEW)]


_PATCHES = (("exit-unload", _exit_unload), ("keep-instance", _keep_instance), ("error-status", _error_status),
            ("error-message", _error_message), ("step-terminated", _step_terminated),
            ("restore-terminated", _restore_terminated), ("free-once", _free_once))


def patch_pythonfmu_binary(data: bytes) -> tuple[bytes, dict[str, str]]:
    """Apply the patches to pythonfmu 0.7.0's ``libpythonfmu-export.so``.

    Returns (data, notes): notes maps each patch name to "patched", "already patched" or why
    it was left out. The status patches (``STATUS_PATCHES``) go in all together or not at all.
    """
    try:
        elf = _Elf(data)
    except (PatchMismatch, struct.error, ValueError) as exc:
        return data, {name: f"left as is: {exc}" for name, _ in _PATCHES}
    notes, edits = {}, {}
    for name, locate in _PATCHES:
        try:
            spots = locate(elf, data)
        except (PatchMismatch, struct.error, ValueError) as exc:
            notes[name] = f"left as is: {exc}"
            continue
        state = []
        for at, old, new in spots:
            here = data[at:at + len(new)]
            if here == new:
                state.append("already")
            elif here == old:
                state.append("patch")
            else:
                state = None
                break
        if state is None:
            notes[name] = "left as is: unexpected bytes"
            continue
        notes[name] = "already patched" if set(state) == {"already"} else "patched"
        edits[name] = spots
    if any(not notes[n].endswith("patched") for n in STATUS_PATCHES):
        for n in STATUS_PATCHES:
            if notes[n].endswith("patched") and notes[n] != "already patched":
                notes[n] = "left as is: another status patch does not apply"
                edits.pop(n, None)
    out = bytearray(data)
    for name, spots in edits.items():
        for at, _old, new in spots:
            out[at:at + len(new)] = new
    return bytes(out), notes


def status_patched(notes: dict[str, str]) -> bool:
    """True when every status patch is in the binary."""
    return all(notes.get(n, "").endswith("patched") for n in STATUS_PATCHES)
