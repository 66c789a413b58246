"""The ParaView plugin's XML declares its properties' defaults, which ParaView cannot read from
the VTK classes: each must equal the default of the class it sets (vtkPerceptualLODSelector,
vtkPerceptualLODActor, vtkMultiscaleOctreeBuilder), so that a default changed in the code and
not in the XML fails here instead of giving ParaView users other settings than VTK users."""
import os
import unittest
import xml.etree.ElementTree as ET

from perceptual_lod import (vtkMultiscaleOctreeBuilder, vtkMultiscaleOctreeReader,
                            vtkPerceptualLODSelector)
from perceptual_lod import vtkPerceptualLODActor  # noqa: E402

XML = os.path.join(os.path.dirname(__file__), '..', '..', '..', 'ParaView', 'Plugin',
                   'PerceptualLOD.xml')

# Representation properties the representation itself keeps (ParaView's own, or the
# representation's figures and testing knobs): no VTK class of this project holds their defaults.
REPRESENTATION_OWN = {'Visibility', 'TestingExtraFrameCost', 'TestingSlowRank', 'OwnershipLevel',
                      'Redistribute', 'DiffuseColor', 'Diffuse', 'Specular', 'SpecularPower',
                      'Ambient', 'Opacity'}


def values(text):
    return [float(v) for v in text.split()]


def getter_value(obj, name):
    value = getattr(obj, 'Get' + name)()
    return [float(v) for v in value] if isinstance(value, (tuple, list)) else [float(value)]


class TestPluginDefaults(unittest.TestCase):
    def test_xml_defaults_are_the_classes_defaults(self):
        root = ET.parse(XML).getroot()
        classes = {'vtkMultiscaleOctreeBuilder': vtkMultiscaleOctreeBuilder,
                   'vtkMultiscaleOctreeReader': vtkMultiscaleOctreeReader}
        checked = []
        for proxy in root.iter():
            if proxy.tag not in ('RepresentationProxy', 'SourceProxy'):
                continue
            if proxy.tag == 'RepresentationProxy':
                # the representation forwards these to its actor and the actor's selector
                actor = vtkPerceptualLODActor()
                holders = [actor.GetSelector(), actor, actor.GetBuilder()]
            else:
                holders = [classes[proxy.get('class')]()]
            for prop in proxy:
                default = prop.get('default_values')
                command = prop.get('command') or ''
                if default is None or not command.startswith('Set') or \
                        prop.tag not in ('IntVectorProperty', 'DoubleVectorProperty',
                                         'IdTypeVectorProperty'):
                    continue
                name = command[3:]
                if proxy.tag == 'RepresentationProxy' and prop.get('name') in REPRESENTATION_OWN:
                    continue
                holder = next((h for h in holders if hasattr(h, 'Get' + name)), None)
                what = f"{proxy.get('name')}.{prop.get('name')}"
                self.assertIsNotNone(holder, f'{what}: no class has Get{name}')
                expected = getter_value(holder, name)
                self.assertEqual(values(default), expected,
                                 f'{what}: the XML says {default}, {type(holder).__name__} '
                                 f'defaults to {expected}')
                checked.append(what)
        print(f'{len(checked)} defaults checked: {", ".join(checked)}')
        for must in ('ContourTolerance', 'BrightnessTolerance', 'TopologyTolerance', 'ErrorModel',
                     'TriangleBudget', 'TargetFrameTime', 'MemoryLimit'):
            self.assertTrue(any(w.endswith('.' + must) for w in checked), must)


if __name__ == '__main__':
    unittest.main()
