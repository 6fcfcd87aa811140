"""The edges of a command, shared by both command lines and every file loader.

=========  ====================================================================
module     what it holds
=========  ====================================================================
schema     the keys of every file as typed data (``Key``, its kind, ``check_table``,
           ``read_toml``): each file checked once, one-line errors
cliargs    typed command-line values (argparse types naming the option)
exits      how a command ends: signals as ``Interrupted``, exit codes, ``--debug``
outputs    result files that cannot collide or vanish: atomic writes, held names
bundled    the bundled model files by name (rotor_host/bundled, found as files, never imported)
=========  ====================================================================
"""
