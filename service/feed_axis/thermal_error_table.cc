// Being written: see service/feed_axis/feed_model.h.
