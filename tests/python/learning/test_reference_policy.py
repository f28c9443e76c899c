"""The reference policy reads the task sentence with the language resolver's words."""

from grasp_pipeline.language.config import LanguageConfig
from grasp_pipeline.learning.reference_policy import task_description

TEMPLATE = "pick up the {object} and put it in the tray"


def test_the_description_keeps_the_words_the_resolver_knows():
    cfg = LanguageConfig()
    assert task_description("pick up the red mug and put it in the tray", TEMPLATE, cfg) == "the red mug"
    assert task_description("pick up the blue cuboid and put it in the tray", TEMPLATE, cfg) == "the blue cuboid"
    assert task_description("pick up the yellow triangular prism and put it in the tray", TEMPLATE, cfg) \
        == "the yellow object"
    assert task_description("pick up the soda can and put it in the tray", TEMPLATE, cfg) == "the can"
