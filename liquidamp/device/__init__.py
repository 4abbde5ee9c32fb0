"""The liquid device: parameters, presets, fluid laws, the model family, add-on effects.

Where each equation of Titurus (2018) lives:

- eq. (2)-(6): :mod:`liquidamp.device.fluid`
- Tables 1-3: :mod:`liquidamp.device.presets` (data in ``data/presets.toml``)
- eq. (10) and its reductions (11)-(20): :mod:`liquidamp.device.models`
- ideal characteristics for overlays: :mod:`liquidamp.device.ideal`
"""

from liquidamp.device.params import DeviceParams
from liquidamp.device.presets import (
    DeviceFile,
    device_file_dict,
    load_device,
    load_device_file,
    preset,
    preset_description,
    preset_names,
    write_device_file,
)

__all__ = ["DeviceParams", "preset", "preset_names", "preset_description", "load_device",
           "load_device_file", "DeviceFile", "device_file_dict", "write_device_file"]
