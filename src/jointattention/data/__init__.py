"""Package data: the default data sets, their held-out sets, BlazeFace's and the socket network.

:data:`SHA256` records each file's SHA-256: the package reads them only through
:func:`jointattention._readers.shipped_path`, which checks the sum when a file is first used,
so that a damaged installation is one error line naming the file, not a traceback.
"""

__all__ = ["SHA256"]

# A file replaced on purpose gets its new sum here (sha256sum src/jointattention/data/*).
SHA256 = {
    "blazeface_calibration.npz":
        "564994d130218b842bc8f4bd036963b729750ddddb654e745d8905cf56b78f41",
    "caregiver_125.npz": "33cb1922abc618332aff10caf079011b784d69cc26cbabcdef92251054bd6201",
    "eye_socket_net.npz": "6ce94655f994af4f6da49b21793e340db52a209aff4f97a08f576a33398eb3ac",
    "face_detection_short_range.tflite":
        "3bc182eb9f33925d9e58b5c8d59308a760f4adea8f282370e428c51212c26633",
    "held_out_caregivers.npz":
        "ddc3431d6cd4bbae5814f2d58bc6f8d422e9eaaa3c7a80305ff404054f7979ea",
    "held_out_poses.npz": "9fd8b437fac6d9b4d18a71748ddf9370d397d15e0fecd2213eefe9570630e1d4",
}
