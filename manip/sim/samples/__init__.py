"""Extension samples: `BaseSample` (`base_sample`), `BaseSampleExtension` (`extension`) and `HelloWorld`."""
