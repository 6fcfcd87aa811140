"""What a shared library exports and imports, read from its bytes: ELF (Linux), PE (Windows)
and Mach-O (macOS, thin or universal), with ``struct`` only; and the universal ("fat") Mach-O
writer that joins the x86_64 and arm64 slices of the darwin64 binary.

``exports_and_imports(data)`` -> ``Linkage``: the defined global symbols others can link to,
the symbols taken from elsewhere (ELF: with their symbol version, e.g. ``hypot@GLIBC_2.2.5``),
and the libraries needed. The build checks every binary with it (only the FMI functions
exported; only the C runtime and libm needed), and so do the tests.

Formats: the ELF-64 gABI and the GNU symbol versioning sections; Microsoft's PE/COFF
specification (export and import directories); Apple's <mach-o/loader.h>, <mach-o/nlist.h>
and <mach-o/fat.h> (the fat header and its fat_arch entries are big-endian).
"""

from __future__ import annotations

import struct
from dataclasses import dataclass, field

FAT_MAGIC = 0xCAFEBABE
MH_MAGIC_64 = 0xFEEDFACF
CPU_NAMES = {0x01000007: "x86_64", 0x0100000C: "arm64"}


@dataclass
class Linkage:
    """One binary (one slice of a universal Mach-O): its format, CPU, exports, imports, libraries."""

    format: str  # elf | pe | macho
    cpu: str
    exports: list[str] = field(default_factory=list)
    imports: list[str] = field(default_factory=list)  # ELF: name@VERSION where versioned
    libraries: list[str] = field(default_factory=list)
    min_os: str = ""  # Mach-O: the minimum macOS version (LC_BUILD_VERSION's minos, e.g. "11.0")
    install_name: str = ""  # Mach-O: the dylib's own name (LC_ID_DYLIB)


def _cstr(data: bytes, start: int) -> str:
    return data[start:data.index(b"\0", start)].decode("ascii", "replace")


# ----------------------------------------------------------------------------- ELF

def _elf(data: bytes) -> Linkage:
    if data[4] != 2 or data[5] != 1:
        raise ValueError("only 64-bit little-endian ELF is read")
    machine = struct.unpack_from("<H", data, 18)[0]
    shoff, = struct.unpack_from("<Q", data, 40)
    shentsize, shnum = struct.unpack_from("<HH", data, 58)
    secs = [struct.unpack_from("<IIQQQQIIQQ", data, shoff + k * shentsize) for k in range(shnum)]
    by_type = {}
    for s in secs:
        by_type.setdefault(s[1], s)
    out = Linkage("elf", {62: "x86_64", 183: "aarch64"}.get(machine, str(machine)))
    dyn = by_type.get(6)  # SHT_DYNAMIC
    if dyn:
        strtab = secs[dyn[6]][4]
        for k in range(dyn[5] // 16):
            tag, val = struct.unpack_from("<qQ", data, dyn[4] + 16 * k)
            if tag == 1:  # DT_NEEDED
                out.libraries.append(_cstr(data, strtab + val))
    sym = by_type.get(11)  # SHT_DYNSYM
    if not sym:
        return out
    strtab = secs[sym[6]][4]
    versions = {}
    need = by_type.get(0x6FFFFFFE)  # SHT_GNU_verneed: each Verneed, its Vernaux (other, name)
    if need:
        off = need[4]
        while True:
            _v, cnt, _file, aux, nxt = struct.unpack_from("<HHIII", data, off)
            a = off + aux
            for _ in range(cnt):
                _h, _f, other, name, anext = struct.unpack_from("<IHHII", data, a)
                versions[other] = _cstr(data, secs[need[6]][4] + name)
                a += anext
            if not nxt:
                break
            off += nxt
    versym = by_type.get(0x6FFFFFFF)  # SHT_GNU_versym: one half-word per dynamic symbol
    for k in range(1, sym[5] // 24):
        name, info, other, shndx = struct.unpack_from("<IBBH", data, sym[4] + 24 * k)
        text = _cstr(data, strtab + name)
        bind, visibility = info >> 4, other & 3
        if not text or bind == 0:  # local
            continue
        if shndx == 0:
            ver = struct.unpack_from("<H", data, versym[4] + 2 * k)[0] & 0x7FFF if versym else 0
            out.imports.append(f"{text}@{versions[ver]}" if ver in versions else text)
        elif visibility == 0:
            out.exports.append(text)
    return out


# ----------------------------------------------------------------------------- PE

def _pe(data: bytes) -> Linkage:
    pe, = struct.unpack_from("<I", data, 0x3C)
    if data[pe:pe + 4] != b"PE\0\0":
        raise ValueError("not a PE file")
    machine, nsec = struct.unpack_from("<HH", data, pe + 4)
    opt_size, = struct.unpack_from("<H", data, pe + 20)
    opt = pe + 24
    if struct.unpack_from("<H", data, opt)[0] != 0x20B:
        raise ValueError("only PE32+ (64-bit) is read")
    dirs = [struct.unpack_from("<II", data, opt + 112 + 8 * k) for k in range(2)]
    sections = [struct.unpack_from("<IIII", data, opt + opt_size + 40 * k + 8) for k in range(nsec)]

    def at(rva: int) -> int:  # file offset of a relative virtual address
        for vsize, vaddr, rsize, raw in sections:
            if vaddr <= rva < vaddr + max(vsize, rsize):
                return raw + rva - vaddr
        raise ValueError(f"RVA {rva:#x} in no section")

    out = Linkage("pe", {0x8664: "x86_64", 0xAA64: "arm64"}.get(machine, str(machine)))
    rva, size = dirs[0]
    if size:
        e = at(rva)
        n_names, = struct.unpack_from("<I", data, e + 24)
        names, = struct.unpack_from("<I", data, e + 32)
        for k in range(n_names):
            out.exports.append(_cstr(data, at(struct.unpack_from("<I", data, at(names) + 4 * k)[0])))
    rva, size = dirs[1]
    if size:
        d = at(rva)
        while True:
            lookup, _t, _f, name, first = struct.unpack_from("<IIIII", data, d)
            if not (lookup or name or first):
                break
            out.libraries.append(_cstr(data, at(name)))
            t = at(lookup or first)
            while True:
                entry, = struct.unpack_from("<Q", data, t)
                if not entry:
                    break
                out.imports.append(f"#{entry & 0xFFFF}" if entry >> 63 else _cstr(data, at(entry & 0x7FFFFFFF) + 2))
                t += 8
            d += 20
    return out


# ----------------------------------------------------------------------------- Mach-O

def _macho(data: bytes) -> Linkage:
    magic, cpu, _sub, _ft, ncmds, _size, _flags = struct.unpack_from("<IiiIIII", data, 0)
    if magic != MH_MAGIC_64:
        raise ValueError("only 64-bit Mach-O is read")
    out = Linkage("macho", CPU_NAMES.get(cpu, str(cpu)))
    off = 32
    for _ in range(ncmds):
        cmd, size = struct.unpack_from("<II", data, off)
        if cmd in (0xC, 0x80000018, 0x8000001F):  # LC_LOAD_DYLIB, LC_LOAD_WEAK_DYLIB, LC_REEXPORT_DYLIB
            out.libraries.append(_cstr(data, off + struct.unpack_from("<I", data, off + 8)[0]))
        elif cmd == 0xD:  # LC_ID_DYLIB
            out.install_name = _cstr(data, off + struct.unpack_from("<I", data, off + 8)[0])
        elif cmd == 0x32:  # LC_BUILD_VERSION: platform, minos (xxxx.yy.zz nibbles), sdk
            minos, = struct.unpack_from("<I", data, off + 12)
            out.min_os = f"{minos >> 16}.{(minos >> 8) & 0xFF}" + (f".{minos & 0xFF}" if minos & 0xFF else "")
        elif cmd == 0x24:  # LC_VERSION_MIN_MACOSX (older linkers): version, sdk
            v, = struct.unpack_from("<I", data, off + 8)
            out.min_os = f"{v >> 16}.{(v >> 8) & 0xFF}" + (f".{v & 0xFF}" if v & 0xFF else "")
        elif cmd == 0x2:  # LC_SYMTAB: nlist_64 entries
            symoff, nsyms, stroff, _ss = struct.unpack_from("<IIII", data, off + 8)
            for k in range(nsyms):
                strx, ntype, _sect, _desc, _value = struct.unpack_from("<IBBHQ", data, symoff + 16 * k)
                if ntype & 0xE0 or not ntype & 0x01:  # a debugging entry, or not external
                    continue
                name = _cstr(data, stroff + strx)
                if ntype & 0x0E == 0x0E and not ntype & 0x10:  # N_SECT, not a private external
                    out.exports.append(name[1:] if name.startswith("_") else name)
                elif ntype & 0x0E == 0:  # N_UNDF
                    out.imports.append(name[1:] if name.startswith("_") else name)
        off += size
    return out


def fat_slices(data: bytes) -> list[bytes]:
    """The Mach-O files inside a universal binary (or [data] for a thin one)."""
    if struct.unpack_from(">I", data, 0)[0] != FAT_MAGIC:
        return [data]
    n, = struct.unpack_from(">I", data, 4)
    out = []
    for k in range(n):
        _cpu, _sub, offset, size, _align = struct.unpack_from(">iiIII", data, 8 + 20 * k)
        out.append(data[offset:offset + size])
    return out


def fat_binary(slices: list[bytes]) -> bytes:
    """A universal Mach-O of thin 64-bit ``slices``: the fat header, one fat_arch per slice
    (its CPU type and subtype from its own header), each slice at an offset aligned as lipo
    aligns it (2^14 for arm64's 16 KiB pages, 2^12 otherwise)."""
    archs, body, offset = [], [], 8 + 20 * len(slices)
    for s in slices:
        magic, cpu, sub = struct.unpack_from("<Iii", s, 0)
        if magic != MH_MAGIC_64:
            raise ValueError("fat_binary: a slice is not a 64-bit Mach-O file")
        align = 14 if cpu == 0x0100000C else 12
        start = -(-offset // (1 << align)) * (1 << align)
        body.append(b"\0" * (start - offset) + s)
        archs.append(struct.pack(">iiIII", cpu, sub, start, len(s), align))
        offset = start + len(s)
    return struct.pack(">II", FAT_MAGIC, len(slices)) + b"".join(archs) + b"".join(body)


def exports_and_imports(data: bytes) -> list[Linkage]:
    """One ``Linkage`` per binary in ``data``: one for ELF, PE or a thin Mach-O, one per slice of
    a universal Mach-O. ValueError for anything else."""
    if data[:4] == b"\x7fELF":
        return [_elf(data)]
    if data[:2] == b"MZ":
        return [_pe(data)]
    if struct.unpack_from(">I", data, 0)[0] == FAT_MAGIC or struct.unpack_from("<I", data, 0)[0] == MH_MAGIC_64:
        return [_macho(s) for s in fat_slices(data)]
    raise ValueError("not an ELF, PE or Mach-O file")


def glibc_versions(link: Linkage) -> list[tuple[int, ...]]:
    """The GLIBC_x.y versions an ELF binary's imports need, as tuples (sorted)."""
    found = {tuple(int(p) for p in imp.rpartition("@GLIBC_")[2].split("."))
             for imp in link.imports if "@GLIBC_" in imp}
    return sorted(found)


__all__ = ["Linkage", "exports_and_imports", "fat_binary", "fat_slices", "glibc_versions"]
